//! The non-blocking spacenavd client.

use std::collections::VecDeque;
use std::io::{self, Read, Write};
use std::os::unix::net::UnixStream;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crate::SpaceEvent;
use crate::protocol::{
    self, Decoder, Frame, MAX_PROTO_VER, REQ_DEV_NAXES, REQ_DEV_NBUTTONS, REQ_DEV_TYPE,
    REQ_DEV_USBID, REQ_SET_SENS, REQ_TAG,
};

/// Socket path spacenavd and libspnav use by default.
pub const DEFAULT_SOCKET_PATH: &str = "/var/run/spnav.sock";

/// At most this many bytes are read per [`SpaceNav::poll`] (2048 packets); the rest stays
/// in the socket for the next call, which bounds memory and time per call.
const MAX_READ_PER_POLL: usize = 64 * 1024;
/// Events received while waiting for a request response, kept for the next poll.
const MAX_QUEUED_EVENTS: usize = 4096;
/// Response timeout libspnav uses for v1 requests.
const REQUEST_TIMEOUT: Duration = Duration::from_millis(400);

/// Errors of the spacenavd client.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SpaceNavError {
    /// No daemon socket could be connected (daemon not running, no permission, …).
    #[error("cannot connect to spacenavd socket {}: {source}", path.display())]
    Connect {
        /// The (last) socket path tried.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: io::Error,
    },
    /// The daemon closed the connection (it exited or dropped this client); reconnect later.
    #[error("spacenavd closed the connection")]
    Disconnected,
    /// Any other socket error.
    #[error("spacenavd socket I/O error: {0}")]
    Io(#[from] io::Error),
    /// The call needs protocol v1 but the connection uses the given older version.
    #[error("request needs spacenavd protocol v1 (connection uses v{0})")]
    ProtocolUnsupported(u32),
    /// The daemon did not answer a request in time.
    #[error("spacenavd did not answer request {request:#06x} in time")]
    Timeout {
        /// Request code (without [`REQ_TAG`]).
        request: u32,
    },
    /// The daemon answered a request with a failure status.
    #[error("spacenavd rejected request {request:#06x} (status {status})")]
    RequestFailed {
        /// Request code (without [`REQ_TAG`]).
        request: u32,
        /// Status word of the response (negative).
        status: i32,
    },
    /// A sensitivity must be a finite number.
    #[error("sensitivity must be finite, got {0}")]
    InvalidSensitivity(f32),
}

/// Device properties queried with protocol v1 ([`SpaceNav::device_info`]); `None` where the
/// daemon answered with a failure (e.g. no device, or no USB id for a serial device).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct DeviceInfo {
    /// Number of axes (6 for 6-DoF devices).
    pub num_axes: Option<u32>,
    /// Number of buttons.
    pub num_buttons: Option<u32>,
    /// USB `[vendor, product]` id.
    pub usb_id: Option<[u16; 2]>,
    /// spacenavd device type (`DEV_*` in spacenavd's `proto.h`).
    pub device_type: Option<i32>,
}

/// The value of a `socket = PATH` line of an spnavrc file (as libspnav reads
/// `/etc/spnavrc`), if any. `#` starts a comment line.
pub fn parse_spnavrc_socket(text: &str) -> Option<PathBuf> {
    text.lines().find_map(|line| {
        let line = line.trim();
        if line.starts_with('#') {
            return None;
        }
        let (key, value) = line.split_once('=')?;
        let value = value.trim();
        (key.trim() == "socket" && !value.is_empty()).then(|| PathBuf::from(value))
    })
}

/// Socket paths [`SpaceNav::connect`] tries, in order, like libspnav's `spnav_open`:
/// `$SPNAV_SOCKET` (if set and non-empty), the `socket` of `/etc/spnavrc`, then
/// [`DEFAULT_SOCKET_PATH`].
pub fn socket_path_candidates() -> Vec<PathBuf> {
    let mut paths = Vec::new();
    if let Some(p) = std::env::var_os("SPNAV_SOCKET").filter(|p| !p.is_empty()) {
        paths.push(PathBuf::from(p));
    }
    if let Some(p) = std::fs::read_to_string("/etc/spnavrc")
        .ok()
        .and_then(|t| parse_spnavrc_socket(&t))
    {
        paths.push(p);
    }
    let default = PathBuf::from(DEFAULT_SOCKET_PATH);
    if !paths.contains(&default) {
        paths.push(default);
    }
    paths
}

/// A connection to spacenavd.
///
/// The socket is non-blocking: [`poll`](Self::poll) never waits. Only the v1 helpers
/// ([`negotiate_protocol`](Self::negotiate_protocol), [`device_info`](Self::device_info),
/// [`set_sensitivity`](Self::set_sensitivity) in v1) block, up to their timeout.
#[derive(Debug)]
pub struct SpaceNav {
    stream: UnixStream,
    path: PathBuf,
    decoder: Decoder,
    /// Events received while a blocking call waited; returned first by `poll`.
    queued: VecDeque<SpaceEvent>,
    /// v1 responses received while a request is in flight.
    responses: VecDeque<[i32; 8]>,
    protocol: u32,
    negotiating: bool,
    awaiting_response: bool,
    closed: bool,
}

impl SpaceNav {
    /// Connects like libspnav: tries [`socket_path_candidates`] in order. Uses protocol v0.
    pub fn connect() -> Result<Self, SpaceNavError> {
        let mut last = None;
        for path in socket_path_candidates() {
            match Self::connect_to(&path) {
                Ok(nav) => return Ok(nav),
                Err(e) => last = Some(e),
            }
        }
        Err(last.unwrap_or_else(|| SpaceNavError::Connect {
            path: PathBuf::from(DEFAULT_SOCKET_PATH),
            source: io::ErrorKind::NotFound.into(),
        }))
    }

    /// Connects to the daemon socket at `path`. Uses protocol v0 (what spacenavd assumes
    /// for clients that do not ask for more), which works with every spacenavd version.
    pub fn connect_to(path: impl AsRef<Path>) -> Result<Self, SpaceNavError> {
        let path = path.as_ref().to_path_buf();
        let connect_err = |source| SpaceNavError::Connect {
            path: path.clone(),
            source,
        };
        let stream = UnixStream::connect(&path).map_err(connect_err)?;
        stream.set_nonblocking(true).map_err(connect_err)?;
        Ok(Self {
            stream,
            path,
            decoder: Decoder::default(),
            queued: VecDeque::new(),
            responses: VecDeque::new(),
            protocol: 0,
            negotiating: false,
            awaiting_response: false,
            closed: false,
        })
    }

    /// The socket path this client is connected to.
    pub fn socket_path(&self) -> &Path {
        &self.path
    }

    /// Protocol version in use: 0 unless [`negotiate_protocol`](Self::negotiate_protocol)
    /// upgraded it.
    pub fn protocol_version(&self) -> u32 {
        self.protocol
    }

    /// Returns all events available now, without blocking. Partial packets stay buffered
    /// for the next call; unknown packet types are skipped. At most 64 KiB (2048 packets)
    /// are read per call.
    ///
    /// When the daemon closes the connection, events decoded before the end are still
    /// returned; the following call returns [`SpaceNavError::Disconnected`] (drop this
    /// client and [`connect`](Self::connect) again later).
    pub fn poll(&mut self) -> Result<Vec<SpaceEvent>, SpaceNavError> {
        let mut events: Vec<SpaceEvent> = self.queued.drain(..).collect();
        let mut buf = [0u8; 4096];
        let mut total = 0;
        while !self.closed && total < MAX_READ_PER_POLL {
            match self.stream.read(&mut buf) {
                Ok(0) => self.closed = true,
                Ok(n) => {
                    total += n;
                    self.decoder.push(&buf[..n]);
                    self.drain_frames(&mut events);
                }
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => break,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) if is_disconnect(&e) => self.closed = true,
                Err(e) => {
                    self.queued.extend(events);
                    self.trim_queue();
                    return Err(e.into());
                }
            }
        }
        if self.closed && events.is_empty() {
            return Err(SpaceNavError::Disconnected);
        }
        Ok(events)
    }

    /// Asks the daemon to switch to protocol v1 (libspnav's handshake: one `i32`
    /// `0x7faa5501` — a NaN as `f32`). Returns the version in use afterwards.
    ///
    /// A v1-capable spacenavd answers immediately; an old daemon answers nothing, so after
    /// `timeout` (libspnav uses 300 ms) the client stays on v0 and, like libspnav, re-sends
    /// sensitivity 1.0 in case the old daemon took the request as a sensitivity value.
    /// Events arriving meanwhile are kept for the next [`poll`](Self::poll).
    /// In v1 the daemon also sends [`SpaceEvent::Device`] hot-plug events.
    pub fn negotiate_protocol(&mut self, timeout: Duration) -> Result<u32, SpaceNavError> {
        if self.protocol >= MAX_PROTO_VER {
            return Ok(self.protocol);
        }
        let deadline = Instant::now() + timeout;
        let word = protocol::change_proto_word(MAX_PROTO_VER);
        self.write_all(&word.to_ne_bytes(), deadline)?;
        self.decoder.expect_proto_reply = true;
        self.negotiating = true;
        while self.negotiating {
            self.drain_into_queue();
            if !self.negotiating {
                break;
            }
            if !self.read_until(deadline)? {
                break;
            }
        }
        self.drain_into_queue();
        if self.negotiating {
            // Old daemon: no answer. A late answer is still consumed by the decoder (the
            // flag stays set) but no longer changes the protocol.
            self.negotiating = false;
            let restore = 1.0f32.to_bits().to_ne_bytes();
            self.write_all(&restore, Instant::now() + REQUEST_TIMEOUT)?;
        }
        Ok(self.protocol)
    }

    /// Sets this client's sensitivity multiplier (applied by the daemon to motion values).
    /// In v0 the value is written without confirmation; in v1 it is a request answered by
    /// the daemon.
    pub fn set_sensitivity(&mut self, sensitivity: f32) -> Result<(), SpaceNavError> {
        if !sensitivity.is_finite() {
            return Err(SpaceNavError::InvalidSensitivity(sensitivity));
        }
        if self.protocol == 0 {
            let bytes = sensitivity.to_bits().to_ne_bytes();
            return self.write_all(&bytes, Instant::now() + REQUEST_TIMEOUT);
        }
        let mut data = [0i32; 7];
        data[0] = sensitivity.to_bits() as i32;
        let resp = self.request(REQ_SET_SENS, data, REQUEST_TIMEOUT)?;
        match resp[6] {
            status if status < 0 => Err(SpaceNavError::RequestFailed {
                request: REQ_SET_SENS,
                status,
            }),
            _ => Ok(()),
        }
    }

    /// Queries the device's axes, buttons, USB id and type (protocol v1 only; each request
    /// waits up to `timeout`).
    pub fn device_info(&mut self, timeout: Duration) -> Result<DeviceInfo, SpaceNavError> {
        let mut ask = |req: u32| -> Result<Option<[i32; 7]>, SpaceNavError> {
            let resp = self.request(req, [0; 7], timeout)?;
            Ok((resp[6] >= 0).then_some(resp))
        };
        Ok(DeviceInfo {
            num_axes: ask(REQ_DEV_NAXES)?.map(|r| r[0].max(0) as u32),
            num_buttons: ask(REQ_DEV_NBUTTONS)?.map(|r| r[0].max(0) as u32),
            usb_id: ask(REQ_DEV_USBID)?.map(|r| [r[0] as u16, r[1] as u16]),
            device_type: ask(REQ_DEV_TYPE)?.map(|r| r[0]),
        })
    }

    /// Sends a v1 request and waits for its response; returns the response data words.
    fn request(
        &mut self,
        request: u32,
        data: [i32; 7],
        timeout: Duration,
    ) -> Result<[i32; 7], SpaceNavError> {
        if self.protocol < 1 {
            return Err(SpaceNavError::ProtocolUnsupported(self.protocol));
        }
        let deadline = Instant::now() + timeout;
        let tag = (REQ_TAG | request) as i32;
        let mut words = [0i32; 8];
        words[0] = tag;
        words[1..].copy_from_slice(&data);
        self.responses.clear();
        self.awaiting_response = true;
        let result = self
            .write_all(&protocol::encode_packet(&words), deadline)
            .and_then(|()| {
                loop {
                    self.drain_into_queue();
                    while let Some(resp) = self.responses.pop_front() {
                        if resp[0] == tag {
                            let mut out = [0i32; 7];
                            out.copy_from_slice(&resp[1..]);
                            return Ok(out);
                        }
                    }
                    if !self.read_until(deadline)? {
                        return Err(SpaceNavError::Timeout { request });
                    }
                }
            });
        self.awaiting_response = false;
        self.responses.clear();
        result
    }

    /// Moves decoded frames: events into `events`, protocol answers into the client state.
    fn drain_frames(&mut self, events: &mut Vec<SpaceEvent>) {
        while let Some(frame) = self.decoder.next_frame() {
            match frame {
                Frame::Event(ev) => events.push(ev),
                Frame::Skipped => {}
                Frame::ProtoReply(version) => {
                    if self.negotiating {
                        self.protocol = version.min(MAX_PROTO_VER);
                        self.negotiating = false;
                    }
                }
                Frame::Response(words) => {
                    if self.awaiting_response && self.responses.len() < 16 {
                        self.responses.push_back(words);
                    }
                }
            }
        }
    }

    fn drain_into_queue(&mut self) {
        let mut events = Vec::new();
        self.drain_frames(&mut events);
        self.queued.extend(events);
        self.trim_queue();
    }

    fn trim_queue(&mut self) {
        while self.queued.len() > MAX_QUEUED_EVENTS {
            self.queued.pop_front();
        }
    }

    /// Blocks until some bytes arrive or `deadline` passes; `Ok(false)` on timeout.
    fn read_until(&mut self, deadline: Instant) -> Result<bool, SpaceNavError> {
        if self.closed {
            return Err(SpaceNavError::Disconnected);
        }
        let now = Instant::now();
        if now >= deadline {
            return Ok(false);
        }
        let wait = (deadline - now).max(Duration::from_millis(1));
        let mut buf = [0u8; 4096];
        self.stream.set_nonblocking(false)?;
        let result = self
            .stream
            .set_read_timeout(Some(wait))
            .and_then(|()| self.stream.read(&mut buf));
        self.stream.set_nonblocking(true)?;
        match result {
            Ok(0) => {
                self.closed = true;
                Err(SpaceNavError::Disconnected)
            }
            Ok(n) => {
                self.decoder.push(&buf[..n]);
                Ok(true)
            }
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::WouldBlock
                        | io::ErrorKind::TimedOut
                        | io::ErrorKind::Interrupted
                ) =>
            {
                Ok(Instant::now() < deadline)
            }
            Err(e) if is_disconnect(&e) => {
                self.closed = true;
                Err(SpaceNavError::Disconnected)
            }
            Err(e) => Err(e.into()),
        }
    }

    /// Writes all of `bytes` on the non-blocking socket, retrying until `deadline`.
    fn write_all(&mut self, mut bytes: &[u8], deadline: Instant) -> Result<(), SpaceNavError> {
        while !bytes.is_empty() {
            match self.stream.write(bytes) {
                Ok(0) => return Err(SpaceNavError::Disconnected),
                Ok(n) => bytes = &bytes[n..],
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => {
                    if Instant::now() >= deadline {
                        return Err(e.into());
                    }
                    std::thread::sleep(Duration::from_millis(1));
                }
                Err(e) if is_disconnect(&e) => {
                    self.closed = true;
                    return Err(SpaceNavError::Disconnected);
                }
                Err(e) => return Err(e.into()),
            }
        }
        Ok(())
    }
}

fn is_disconnect(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::ConnectionReset
            | io::ErrorKind::ConnectionAborted
            | io::ErrorKind::BrokenPipe
            | io::ErrorKind::NotConnected
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spnavrc_socket_line() {
        let rc = "# comment\n  sensitivity = 2\n# socket = /nope\n socket =  /tmp/x.sock  \n";
        assert_eq!(parse_spnavrc_socket(rc), Some(PathBuf::from("/tmp/x.sock")));
        assert_eq!(parse_spnavrc_socket("socket =\n"), None);
        assert_eq!(parse_spnavrc_socket("sockets = /a\n"), None);
        assert_eq!(parse_spnavrc_socket(""), None);
    }

    #[test]
    fn candidates_end_with_default() {
        let c = socket_path_candidates();
        assert!(c.contains(&PathBuf::from(DEFAULT_SOCKET_PATH)));
    }

    #[test]
    fn connect_to_missing_socket_is_typed_error() {
        let err = SpaceNav::connect_to("/nonexistent-dir-cadre/spnav.sock").unwrap_err();
        assert!(matches!(err, SpaceNavError::Connect { .. }), "{err}");
        assert!(
            err.to_string()
                .contains("/nonexistent-dir-cadre/spnav.sock")
        );
    }
}
