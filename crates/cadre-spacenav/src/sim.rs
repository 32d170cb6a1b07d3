//! A simulated spacenavd for tests and manual runs.
//!
//! [`SimDaemon`] listens on a Unix socket, accepts clients in a background thread and writes
//! the exact packets spacenavd writes (see [`crate::protocol`]). Like spacenavd it starts
//! every client on protocol v0, applies a v0 client's sensitivity to motion values, answers
//! the protocol-change handshake (unless configured as an old daemon with
//! [`SimConfig::max_protocol`] = 0) and answers the v1 device queries.
//!
//! Sending never blocks: bytes a client's socket buffer cannot take yet are queued per
//! client (up to 4 MiB, beyond which packets are dropped, as spacenavd drops them) and
//! written by the background thread.
//!
//! ```no_run
//! use cadre_spacenav::{SpaceNav, sim::SimDaemon};
//! let daemon = SimDaemon::bind("/tmp/test-spnav.sock").unwrap();
//! let mut nav = SpaceNav::connect_to(daemon.path()).unwrap();
//! assert!(daemon.wait_for_clients(1, std::time::Duration::from_secs(5)));
//! daemon.send_motion([0, 0, 0], [0, 120, 0], 16);
//! daemon.send_button(0, true);
//! // ... nav.poll() until the events arrive.
//! # let _ = nav.poll();
//! ```

use std::io::{self, Read, Write};
use std::os::unix::fs::FileTypeExt;
use std::os::unix::net::{UnixListener, UnixStream};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::protocol::{
    self, PACKET_LEN, REQ_DEV_NAXES, REQ_DEV_NBUTTONS, REQ_DEV_TYPE, REQ_DEV_USBID, REQ_GET_SENS,
    REQ_SET_SENS,
};

/// Behaviour of a [`SimDaemon`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SimConfig {
    /// Highest protocol version to grant (1 = current spacenavd; 0 = an old daemon that
    /// ignores the protocol-change handshake).
    pub max_protocol: u32,
    /// Answer to the v1 number-of-axes query.
    pub num_axes: i32,
    /// Answer to the v1 number-of-buttons query.
    pub num_buttons: i32,
    /// Answer to the v1 USB id query (`None`: fail, as for a serial device).
    pub usb_id: Option<[u16; 2]>,
    /// Answer to the v1 device type query.
    pub device_type: i32,
}

impl Default for SimConfig {
    /// A current spacenavd with a SpaceNavigator (6 axes, 2 buttons, USB 046d:c626, type 0x206).
    fn default() -> Self {
        Self {
            max_protocol: 1,
            num_axes: 6,
            num_buttons: 2,
            usb_id: Some([0x046d, 0xc626]),
            device_type: 0x206,
        }
    }
}

#[derive(Debug)]
struct SimClient {
    stream: UnixStream,
    inbuf: Vec<u8>,
    outbuf: Vec<u8>,
    proto: u32,
    sensitivity: f32,
    alive: bool,
}

/// Bytes queued for one client beyond what its socket buffer takes; more is dropped, as
/// spacenavd drops packets a client does not read.
const MAX_OUTBUF: usize = 4 * 1024 * 1024;

impl SimClient {
    fn new(stream: UnixStream) -> Self {
        Self {
            stream,
            inbuf: Vec::new(),
            outbuf: Vec::new(),
            proto: 0,
            sensitivity: 1.0,
            alive: true,
        }
    }

    /// Queues whole packets and writes what the socket takes now; the background thread
    /// writes the rest, so senders never block on a client that is not reading yet.
    fn send(&mut self, bytes: &[u8]) {
        if self.alive && self.outbuf.len() + bytes.len() <= MAX_OUTBUF {
            self.outbuf.extend_from_slice(bytes);
            self.flush();
        }
    }

    fn flush(&mut self) {
        while self.alive && !self.outbuf.is_empty() {
            match self.stream.write(&self.outbuf) {
                Ok(0) => self.alive = false,
                Ok(n) => {
                    self.outbuf.drain(..n);
                }
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => break,
                Err(_) => self.alive = false,
            }
        }
    }

    /// Reads what the client sent and answers it, as spacenavd's `handle_uevents` does.
    fn service(&mut self, config: &SimConfig) {
        let mut buf = [0u8; 1024];
        loop {
            match self.stream.read(&mut buf) {
                Ok(0) => {
                    self.alive = false;
                    return;
                }
                Ok(n) => {
                    self.inbuf.extend_from_slice(&buf[..n]);
                    if self.inbuf.len() > 64 * 1024 {
                        self.alive = false;
                        return;
                    }
                }
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => break,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(_) => {
                    self.alive = false;
                    return;
                }
            }
        }
        while self.alive {
            if self.proto == 0 {
                let Some(word) = self.inbuf.get(..4) else {
                    break;
                };
                let word = u32::from_ne_bytes([word[0], word[1], word[2], word[3]]);
                self.inbuf.drain(..4);
                if let Some(requested) = protocol::proto_version_of(word) {
                    if config.max_protocol >= 1 {
                        let granted = requested.min(config.max_protocol);
                        self.proto = granted;
                        self.send(&protocol::change_proto_word(granted).to_ne_bytes());
                    }
                    // An old daemon sees a NaN sensitivity and ignores it.
                } else {
                    let sens = f32::from_bits(word);
                    if sens.is_finite() {
                        self.sensitivity = sens;
                    }
                }
            } else {
                let Some(packet) = self.inbuf.get(..PACKET_LEN) else {
                    break;
                };
                let packet: [u8; PACKET_LEN] = packet.try_into().expect("32 bytes");
                self.inbuf.drain(..PACKET_LEN);
                let reply = self.answer(protocol::decode_words(&packet), config);
                self.send(&protocol::encode_packet(&reply));
            }
        }
    }

    /// The response to a v1 request: same type word, status in the last word.
    fn answer(&mut self, mut words: [i32; 8], config: &SimConfig) -> [i32; 8] {
        let status = match words[0] as u32 & 0xffff {
            REQ_SET_SENS => {
                let sens = f32::from_bits(words[1] as u32);
                if sens.is_finite() {
                    self.sensitivity = sens;
                    0
                } else {
                    -1
                }
            }
            REQ_GET_SENS => {
                words[1] = self.sensitivity.to_bits() as i32;
                0
            }
            REQ_DEV_NAXES => {
                words[1] = config.num_axes;
                0
            }
            REQ_DEV_NBUTTONS => {
                words[1] = config.num_buttons;
                0
            }
            REQ_DEV_USBID => match config.usb_id {
                Some([vendor, product]) => {
                    words[1] = i32::from(vendor);
                    words[2] = i32::from(product);
                    0
                }
                None => -1,
            },
            REQ_DEV_TYPE => {
                words[1] = config.device_type;
                0
            }
            _ => -1,
        };
        words[7] = status;
        words
    }
}

#[derive(Debug)]
struct Shared {
    clients: Mutex<Vec<SimClient>>,
    stop: AtomicBool,
    config: SimConfig,
}

impl Shared {
    fn clients(&self) -> MutexGuard<'_, Vec<SimClient>> {
        // A panic while holding the lock leaves plain data; keep going.
        self.clients.lock().unwrap_or_else(|p| p.into_inner())
    }
}

/// A simulated spacenavd listening on a Unix socket; stops and removes the socket file when
/// dropped.
#[derive(Debug)]
pub struct SimDaemon {
    path: PathBuf,
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
}

impl SimDaemon {
    /// Binds `path` with [`SimConfig::default`] (a current, v1-capable spacenavd).
    pub fn bind(path: impl AsRef<Path>) -> io::Result<Self> {
        Self::bind_with(path, SimConfig::default())
    }

    /// Binds `path` and starts accepting clients in a background thread. A stale socket
    /// file at `path` is replaced (as spacenavd does); any other existing file is an error.
    pub fn bind_with(path: impl AsRef<Path>, config: SimConfig) -> io::Result<Self> {
        let path = path.as_ref().to_path_buf();
        if let Ok(meta) = std::fs::symlink_metadata(&path)
            && meta.file_type().is_socket()
        {
            std::fs::remove_file(&path)?;
        }
        let listener = UnixListener::bind(&path)?;
        listener.set_nonblocking(true)?;
        let shared = Arc::new(Shared {
            clients: Mutex::new(Vec::new()),
            stop: AtomicBool::new(false),
            config,
        });
        let thread_shared = Arc::clone(&shared);
        let thread = std::thread::Builder::new()
            .name("spacenav-sim".into())
            .spawn(move || run(&listener, &thread_shared))?;
        Ok(Self {
            path,
            shared,
            thread: Some(thread),
        })
    }

    /// The socket path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Number of connected clients.
    pub fn client_count(&self) -> usize {
        self.shared.clients().iter().filter(|c| c.alive).count()
    }

    /// Waits until at least `n` clients are connected; `false` on timeout.
    pub fn wait_for_clients(&self, n: usize, timeout: Duration) -> bool {
        let deadline = Instant::now() + timeout;
        loop {
            if self.client_count() >= n {
                return true;
            }
            if Instant::now() >= deadline {
                return false;
            }
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    /// Protocol version of each connected client (in connection order).
    pub fn client_protocols(&self) -> Vec<u32> {
        self.shared.clients().iter().map(|c| c.proto).collect()
    }

    /// Sensitivity each connected client has set (1.0 by default).
    pub fn client_sensitivities(&self) -> Vec<f32> {
        self.shared
            .clients()
            .iter()
            .map(|c| c.sensitivity)
            .collect()
    }

    /// Sends a motion event to every client, scaled by the client's sensitivity as
    /// spacenavd does. Returns the number of clients written to.
    pub fn send_motion(&self, translation: [i32; 3], rotation: [i32; 3], period_ms: u32) -> usize {
        self.for_each_client(|c| {
            let scale = |v: i32| (v as f32 * c.sensitivity) as i32;
            let packet =
                protocol::motion_packet(translation.map(scale), rotation.map(scale), period_ms);
            c.send(&packet);
        })
    }

    /// Sends a button press (`pressed`) or release to every client.
    pub fn send_button(&self, number: u32, pressed: bool) -> usize {
        let packet = protocol::button_packet(number, pressed);
        self.for_each_client(|c| c.send(&packet))
    }

    /// Sends a device added/removed event to the protocol-v1 clients (spacenavd's default
    /// event mask sends these to v1 clients only). Returns the number of v1 clients.
    pub fn send_device(&self, added: bool, id: i32) -> usize {
        let usb = self.shared.config.usb_id.unwrap_or([0, 0]);
        let packet = protocol::device_packet(added, id, self.shared.config.device_type, usb);
        let mut clients = self.shared.clients();
        let mut n = 0;
        for c in clients.iter_mut().filter(|c| c.alive && c.proto >= 1) {
            c.send(&packet);
            n += usize::from(c.alive);
        }
        clients.retain(|c| c.alive);
        n
    }

    /// Writes arbitrary bytes to every client (partial packets, garbage).
    pub fn send_raw(&self, bytes: &[u8]) -> usize {
        self.for_each_client(|c| c.send(bytes))
    }

    /// Closes every client connection (clients see end of stream after the bytes already
    /// sent; bytes still queued for a client that is not reading are dropped).
    pub fn disconnect_all(&self) {
        let mut clients = self.shared.clients();
        for c in clients.iter_mut() {
            c.flush();
            // Ignore errors: the peer may already be gone.
            let _ = c.stream.shutdown(std::net::Shutdown::Both);
        }
        clients.clear();
    }

    fn for_each_client(&self, mut f: impl FnMut(&mut SimClient)) -> usize {
        let mut clients = self.shared.clients();
        let mut n = 0;
        for c in clients.iter_mut().filter(|c| c.alive) {
            f(c);
            n += usize::from(c.alive);
        }
        clients.retain(|c| c.alive);
        n
    }
}

impl Drop for SimDaemon {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Relaxed);
        if let Some(thread) = self.thread.take() {
            // A panicked sim thread has nothing left to clean up.
            let _ = thread.join();
        }
        self.disconnect_all();
        // Best effort: the file may already have been removed.
        let _ = std::fs::remove_file(&self.path);
    }
}

/// Background loop: accept new clients, serve client requests.
fn run(listener: &UnixListener, shared: &Shared) {
    while !shared.stop.load(Ordering::Relaxed) {
        loop {
            match listener.accept() {
                Ok((stream, _)) => {
                    if stream.set_nonblocking(true).is_ok() {
                        shared.clients().push(SimClient::new(stream));
                    }
                }
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(_) => break,
            }
        }
        {
            let mut clients = shared.clients();
            for c in clients.iter_mut() {
                c.flush();
                c.service(&shared.config);
            }
            clients.retain(|c| c.alive);
        }
        std::thread::sleep(Duration::from_millis(1));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn answers_v1_requests() {
        let (a, _b) = UnixStream::pair().unwrap();
        let mut c = SimClient::new(a);
        c.proto = 1;
        let cfg = SimConfig::default();
        let tag = protocol::REQ_TAG as i32;
        let r = c.answer([tag | REQ_DEV_NBUTTONS as i32, 0, 0, 0, 0, 0, 0, 0], &cfg);
        assert_eq!((r[1], r[7]), (2, 0));
        let r = c.answer([tag | 0x3000, 0, 0, 0, 0, 0, 0, 0], &cfg);
        assert_eq!(r[7], -1);
        let no_usb = SimConfig {
            usb_id: None,
            ..cfg
        };
        let r = c.answer([tag | REQ_DEV_USBID as i32, 0, 0, 0, 0, 0, 0, 0], &no_usb);
        assert_eq!(r[7], -1);
    }
}
