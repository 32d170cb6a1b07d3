//! Wire format of the spacenavd Unix-socket protocol (the one libspnav speaks).
//!
//! Everything on the wire is made of native-endian 32-bit integers:
//!
//! * **Daemon → client, events** (protocol v0 and v1): fixed packets of 8 × `i32`
//!   ([`PACKET_LEN`] = 32 bytes). `[0]` is the event type ([`UEV_MOTION`], [`UEV_PRESS`],
//!   [`UEV_RELEASE`], and in v1 also [`UEV_DEV`], [`UEV_CFG`], …).
//!   Motion: `[1..=6]` = x, y, z, rx, ry, rz; `[7]` = period in milliseconds since the
//!   previous motion event of that device. Button: `[1]` = button number.
//! * **Client → daemon, protocol v0**: single `i32`s. A finite `f32` bit pattern sets the
//!   client's sensitivity; the "magic NaN" [`REQ_TAG`]` | `[`REQ_CHANGE_PROTO`]` | version`
//!   asks to switch protocol. A daemon that knows v1 answers with one `i32` of the same form
//!   carrying the version it switched to; an older daemon answers nothing.
//! * **Client ↔ daemon, protocol v1 requests**: 8 × `i32` (`type`, `data[0..7]`), `type` =
//!   [`REQ_TAG`]` | request`; the daemon answers with the same layout, status in `data[6]`
//!   (negative = failure). Responses are told apart from events by the tag in word 0.
//!
//! Source: spacenavd `src/proto.h`, `src/proto_unix.c` (`send_uevent`, `handle_uevents`),
//! libspnav `src/proto.h`, `src/spnav.c` (`spnav_open`, `proc_event`).

use crate::SpaceEvent;

/// Size in bytes of one event packet or v1 request/response: 8 native-endian `i32`s.
pub const PACKET_LEN: usize = 32;
/// Event type word: 6-DoF motion.
pub const UEV_MOTION: i32 = 0;
/// Event type word: button pressed.
pub const UEV_PRESS: i32 = 1;
/// Event type word: button released.
pub const UEV_RELEASE: i32 = 2;
/// Event type word (v1 only): device added or removed.
pub const UEV_DEV: i32 = 3;
/// Event type word (v1 only, when enabled by the event mask): configuration changed.
pub const UEV_CFG: i32 = 4;

/// Tag in the high 16 bits of every request/response type word. As an `f32` bit pattern it
/// is a NaN, which old daemons reject as a sensitivity value.
pub const REQ_TAG: u32 = 0x7faa_0000;
/// Mask selecting the tag bits of a type word.
pub const REQ_TAG_MASK: u32 = 0xffff_0000;
/// Protocol-change request (sent as one `i32`: `REQ_TAG | REQ_CHANGE_PROTO | version`).
pub const REQ_CHANGE_PROTO: u32 = 0x5500;
/// v1 request: set this client's sensitivity (`data[0]` = `f32` bits).
pub const REQ_SET_SENS: u32 = 0x1001;
/// v1 request: get this client's sensitivity (response `data[0]` = `f32` bits).
pub const REQ_GET_SENS: u32 = 0x1002;
/// v1 request: number of axes of the device (response `data[0]`).
pub const REQ_DEV_NAXES: u32 = 0x2002;
/// v1 request: number of buttons of the device (response `data[0]`).
pub const REQ_DEV_NBUTTONS: u32 = 0x2003;
/// v1 request: USB vendor/product id (response `data[0]`, `data[1]`; fails for serial devices).
pub const REQ_DEV_USBID: u32 = 0x2004;
/// v1 request: device type enum (response `data[0]`, see spacenavd `proto.h` `DEV_*`).
pub const REQ_DEV_TYPE: u32 = 0x2005;
/// Highest protocol version this crate speaks.
pub const MAX_PROTO_VER: u32 = 1;

/// The single `i32` word a client sends to ask for protocol `version`.
pub fn change_proto_word(version: u32) -> u32 {
    REQ_TAG | REQ_CHANGE_PROTO | (version & 0xff)
}

/// If `word` is a protocol-change word, the version it names.
pub fn proto_version_of(word: u32) -> Option<u32> {
    ((word & 0xffff_ff00) == (REQ_TAG | REQ_CHANGE_PROTO)).then_some(word & 0xff)
}

/// Encodes 8 words into the 32 bytes written on the socket (native endian).
pub fn encode_packet(words: &[i32; 8]) -> [u8; PACKET_LEN] {
    let mut out = [0u8; PACKET_LEN];
    for (chunk, w) in out.chunks_exact_mut(4).zip(words) {
        chunk.copy_from_slice(&w.to_ne_bytes());
    }
    out
}

/// Decodes 32 bytes read from the socket into 8 words (native endian).
pub fn decode_words(bytes: &[u8; PACKET_LEN]) -> [i32; 8] {
    let mut words = [0i32; 8];
    for (w, chunk) in words.iter_mut().zip(bytes.chunks_exact(4)) {
        *w = i32::from_ne_bytes([chunk[0], chunk[1], chunk[2], chunk[3]]);
    }
    words
}

/// The packet spacenavd writes for a motion event.
pub fn motion_packet(
    translation: [i32; 3],
    rotation: [i32; 3],
    period_ms: u32,
) -> [u8; PACKET_LEN] {
    let [x, y, z] = translation;
    let [rx, ry, rz] = rotation;
    // spacenavd stores the period in an `int` slot; the bit pattern is kept.
    encode_packet(&[UEV_MOTION, x, y, z, rx, ry, rz, period_ms as i32])
}

/// The packet spacenavd writes for a button press or release.
pub fn button_packet(number: u32, pressed: bool) -> [u8; PACKET_LEN] {
    let kind = if pressed { UEV_PRESS } else { UEV_RELEASE };
    encode_packet(&[kind, number as i32, 0, 0, 0, 0, 0, 0])
}

/// The packet spacenavd (v1) writes when a device is added or removed.
pub fn device_packet(added: bool, id: i32, device_type: i32, usb_id: [u16; 2]) -> [u8; PACKET_LEN] {
    encode_packet(&[
        UEV_DEV,
        if added { 0 } else { 1 },
        id,
        device_type,
        i32::from(usb_id[0]),
        i32::from(usb_id[1]),
        0,
        0,
    ])
}

/// Decodes one event packet; `None` for types this crate does not report (unknown,
/// configuration change, raw axis/button events).
pub fn decode_event(words: &[i32; 8]) -> Option<SpaceEvent> {
    match words[0] {
        UEV_MOTION => Some(SpaceEvent::Motion {
            translation: [words[1], words[2], words[3]],
            rotation: [words[4], words[5], words[6]],
            period_ms: words[7] as u32,
        }),
        UEV_PRESS | UEV_RELEASE => Some(SpaceEvent::Button {
            number: words[1] as u32,
            pressed: words[0] == UEV_PRESS,
        }),
        UEV_DEV => Some(SpaceEvent::Device {
            added: words[1] == 0,
            id: words[2],
            device_type: words[3],
            usb_id: [words[4] as u16, words[5] as u16],
        }),
        _ => None,
    }
}

/// One unit recognised in the daemon → client byte stream.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Frame {
    /// A decoded event packet.
    Event(SpaceEvent),
    /// A 32-byte packet of a type this crate ignores.
    Skipped,
    /// The 4-byte answer to a protocol-change request: the version switched to.
    ProtoReply(u32),
    /// A 32-byte v1 request response (`words[0]` carries [`REQ_TAG`]).
    Response([i32; 8]),
}

/// Incremental parser of the daemon → client stream. Keeps at most one partial packet
/// between calls plus the bytes of the current read.
#[derive(Debug, Default)]
pub(crate) struct Decoder {
    buf: Vec<u8>,
    pos: usize,
    /// Set while a protocol-change answer (a lone 4-byte word) may still arrive.
    pub(crate) expect_proto_reply: bool,
}

impl Decoder {
    /// Appends bytes read from the socket.
    pub(crate) fn push(&mut self, bytes: &[u8]) {
        if self.pos > 0 {
            self.buf.drain(..self.pos);
            self.pos = 0;
        }
        self.buf.extend_from_slice(bytes);
    }

    /// Number of buffered bytes not yet parsed.
    #[cfg(test)]
    pub(crate) fn pending_bytes(&self) -> usize {
        self.buf.len() - self.pos
    }

    /// The next complete frame, if the buffer holds one.
    pub(crate) fn next_frame(&mut self) -> Option<Frame> {
        let rest = &self.buf[self.pos..];
        if rest.len() < 4 {
            return None;
        }
        let first = u32::from_ne_bytes([rest[0], rest[1], rest[2], rest[3]]);
        if self.expect_proto_reply
            && let Some(version) = proto_version_of(first)
        {
            self.pos += 4;
            self.expect_proto_reply = false;
            return Some(Frame::ProtoReply(version));
        }
        let packet: &[u8; PACKET_LEN] = rest.get(..PACKET_LEN)?.try_into().ok()?;
        let words = decode_words(packet);
        self.pos += PACKET_LEN;
        if (first & REQ_TAG_MASK) == REQ_TAG {
            return Some(Frame::Response(words));
        }
        Some(decode_event(&words).map_or(Frame::Skipped, Frame::Event))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn motion_round_trip() {
        let bytes = motion_packet([1, -2, 3], [-4, 5, -6], 16);
        let words = decode_words(&bytes);
        assert_eq!(words, [0, 1, -2, 3, -4, 5, -6, 16]);
        assert_eq!(
            decode_event(&words),
            Some(SpaceEvent::Motion {
                translation: [1, -2, 3],
                rotation: [-4, 5, -6],
                period_ms: 16
            })
        );
    }

    #[test]
    fn button_and_device_packets() {
        let w = decode_words(&button_packet(7, true));
        assert_eq!(w[..2], [UEV_PRESS, 7]);
        assert_eq!(
            decode_event(&decode_words(&button_packet(3, false))),
            Some(SpaceEvent::Button {
                number: 3,
                pressed: false
            })
        );
        assert_eq!(
            decode_event(&decode_words(&device_packet(
                true,
                2,
                0x206,
                [0x046d, 0xc626]
            ))),
            Some(SpaceEvent::Device {
                added: true,
                id: 2,
                device_type: 0x206,
                usb_id: [0x046d, 0xc626]
            })
        );
    }

    #[test]
    fn unknown_types_are_skipped() {
        for t in [UEV_CFG, 5, 6, 99, -1, i32::MIN] {
            assert_eq!(decode_event(&[t, 1, 2, 3, 4, 5, 6, 7]), None);
        }
    }

    #[test]
    fn proto_words() {
        assert_eq!(change_proto_word(1), 0x7faa_5501);
        assert_eq!(proto_version_of(0x7faa_5501), Some(1));
        assert_eq!(proto_version_of(0x7faa_1001), None);
        assert_eq!(proto_version_of(0), None);
        // The request word is a NaN when read as f32, so old daemons ignore it.
        assert!(f32::from_bits(change_proto_word(1)).is_nan());
    }

    #[test]
    fn decoder_handles_splits_and_skips() {
        let mut d = Decoder::default();
        let a = motion_packet([1, 2, 3], [4, 5, 6], 8);
        let junk = encode_packet(&[42, 0, 0, 0, 0, 0, 0, 0]);
        let b = button_packet(1, true);
        let mut stream = Vec::new();
        stream.extend_from_slice(&a);
        stream.extend_from_slice(&junk);
        stream.extend_from_slice(&b);
        // Feed byte by byte: frames appear exactly at packet boundaries.
        let mut frames = Vec::new();
        for byte in &stream {
            d.push(std::slice::from_ref(byte));
            while let Some(f) = d.next_frame() {
                frames.push(f);
            }
            assert!(d.pending_bytes() < PACKET_LEN);
        }
        assert_eq!(frames.len(), 3);
        assert!(matches!(frames[0], Frame::Event(SpaceEvent::Motion { .. })));
        assert_eq!(frames[1], Frame::Skipped);
        assert!(matches!(frames[2], Frame::Event(SpaceEvent::Button { .. })));
    }

    #[test]
    fn decoder_proto_reply_and_responses() {
        // An event may precede the reply; the reply is only 4 bytes.
        let mut d = Decoder {
            expect_proto_reply: true,
            ..Decoder::default()
        };
        d.push(&motion_packet([0; 3], [0; 3], 0));
        d.push(&change_proto_word(1).to_ne_bytes());
        d.push(&encode_packet(&[
            (REQ_TAG | REQ_DEV_NAXES) as i32,
            6,
            0,
            0,
            0,
            0,
            0,
            0,
        ]));
        assert!(matches!(d.next_frame(), Some(Frame::Event(_))));
        assert_eq!(d.next_frame(), Some(Frame::ProtoReply(1)));
        assert!(!d.expect_proto_reply);
        match d.next_frame() {
            Some(Frame::Response(w)) => assert_eq!(w[1], 6),
            other => panic!("unexpected {other:?}"),
        }
        assert_eq!(d.next_frame(), None);
        // Without the flag, a tagged word starts a 32-byte response, not a 4-byte reply.
        d.push(&change_proto_word(1).to_ne_bytes());
        assert_eq!(d.next_frame(), None);
        assert_eq!(d.pending_bytes(), 4);
    }
}
