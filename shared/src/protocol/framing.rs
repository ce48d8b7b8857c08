//! Frames on the wire: a 4-byte big-endian payload length, then a bincode (2.0, serde,
//! standard configuration) payload of at most [`MAX_FRAME`] bytes.
//!
//! Decoding is size-limited, so a hostile length prefix or a hostile length inside the
//! payload cannot make either side allocate more than one frame's worth.

use bincode::config;
use serde::{de::DeserializeOwned, Serialize};
use thiserror::Error;

use super::limits::MAX_FRAME;

/// Why a frame could not be made or read.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum FrameError {
    /// The payload's length (bytes, from the header or as encoded) is over [`MAX_FRAME`].
    #[error("frame of {0} bytes exceeds the {MAX_FRAME}-byte limit")]
    TooLong(usize),
    /// The header announces a payload of zero bytes.
    #[error("empty frame")]
    Empty,
    /// bincode could not encode or decode the payload; holds its error.
    #[error("malformed payload: {0}")]
    Malformed(String),
    /// The payload held this many bytes after one complete message.
    #[error("{0} trailing bytes after the message")]
    Trailing(usize),
}

/// Bytes in the length prefix.
pub const HEADER_LEN: usize = 4;

/// Encodes `msg` as one complete frame (header and payload).
pub fn encode_frame<T: Serialize>(msg: &T) -> Result<Vec<u8>, FrameError> {
    let payload = bincode::serde::encode_to_vec(msg, config::standard())
        .map_err(|e| FrameError::Malformed(e.to_string()))?;
    if payload.len() > MAX_FRAME {
        return Err(FrameError::TooLong(payload.len()));
    }
    let mut frame = Vec::with_capacity(HEADER_LEN + payload.len());
    // MAX_FRAME fits in u32, checked above.
    frame.extend_from_slice(&(payload.len() as u32).to_be_bytes());
    frame.extend_from_slice(&payload);
    Ok(frame)
}

/// The payload length a header announces, refused if it is empty or over the limit.
pub fn payload_len(header: [u8; HEADER_LEN]) -> Result<usize, FrameError> {
    let len = u32::from_be_bytes(header) as usize;
    match len {
        0 => Err(FrameError::Empty),
        n if n > MAX_FRAME => Err(FrameError::TooLong(n)),
        n => Ok(n),
    }
}

/// Decodes one payload (without its header). Trailing bytes are an error: a frame holds
/// exactly one message.
pub fn decode_payload<T: DeserializeOwned>(payload: &[u8]) -> Result<T, FrameError> {
    if payload.len() > MAX_FRAME {
        return Err(FrameError::TooLong(payload.len()));
    }
    let cfg = config::standard().with_limit::<MAX_FRAME>();
    let (msg, used) = bincode::serde::decode_from_slice(payload, cfg)
        .map_err(|e| FrameError::Malformed(e.to_string()))?;
    if used != payload.len() {
        return Err(FrameError::Trailing(payload.len() - used));
    }
    Ok(msg)
}

/// Splits complete frames off the front of a byte buffer (for readers that receive
/// arbitrary chunks). Returns the payload of the first complete frame and the bytes it
/// used, `Ok(None)` if more bytes are needed.
pub fn split_frame(buf: &[u8]) -> Result<Option<(&[u8], usize)>, FrameError> {
    let Some(header) = buf.get(..HEADER_LEN) else {
        return Ok(None);
    };
    let mut h = [0u8; HEADER_LEN];
    h.copy_from_slice(header);
    let len = payload_len(h)?;
    match buf.get(HEADER_LEN..HEADER_LEN + len) {
        Some(payload) => Ok(Some((payload, HEADER_LEN + len))),
        None => Ok(None),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_round_trips_with_its_length_first() {
        let msg = (7u32, String::from("hello"), 1.5f64);
        let frame = encode_frame(&msg).unwrap();
        let len = payload_len(frame[..4].try_into().unwrap()).unwrap();
        assert_eq!(len, frame.len() - 4);
        let back: (u32, String, f64) = decode_payload(&frame[4..]).unwrap();
        assert_eq!(back, msg);
        assert_eq!(split_frame(&frame).unwrap().unwrap().1, frame.len());
        assert_eq!(split_frame(&frame[..frame.len() - 1]).unwrap(), None);
    }

    #[test]
    fn oversized_and_empty_lengths_are_refused_before_reading() {
        let big = ((MAX_FRAME + 1) as u32).to_be_bytes();
        assert_eq!(payload_len(big), Err(FrameError::TooLong(MAX_FRAME + 1)));
        assert_eq!(payload_len([0; 4]), Err(FrameError::Empty));
        assert!(split_frame(&[0xff, 0xff, 0xff, 0xff, 1]).is_err());
    }

    #[test]
    fn a_hostile_inner_length_does_not_allocate() {
        // A Vec<u8> whose varint length claims u64::MAX elements.
        let payload = [0xffu8, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff];
        assert!(decode_payload::<Vec<u8>>(&payload).is_err());
        // Claims 1 MiB with only a few bytes present: refused by the limit, not by a read.
        let mut claim = vec![253u8];
        claim.extend_from_slice(&(1u32 << 20).to_le_bytes());
        assert!(decode_payload::<Vec<u8>>(&claim).is_err());
    }

    #[test]
    fn trailing_bytes_are_an_error() {
        let mut frame = encode_frame(&5u32).unwrap();
        frame.push(0);
        assert_eq!(
            decode_payload::<u32>(&frame[4..]),
            Err(FrameError::Trailing(1))
        );
    }
}
