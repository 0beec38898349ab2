//! Typed errors of encoding and decoding.

/// Why a received report was rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DecodeError {
    /// The report does not have the layout's length.
    #[error("wrong report length: expected {expected} bytes, got {actual}")]
    WrongLength {
        /// Bytes the layout needs.
        expected: usize,
        /// Bytes received.
        actual: usize,
    },
    /// The first byte names a layout version this build does not know.
    #[error("unknown report format version {found} (this build speaks version {supported})")]
    UnknownVersion {
        /// Version byte received.
        found: u8,
        /// Version this build speaks ([`crate::FORMAT_VERSION`]).
        supported: u8,
    },
    /// A field holds a value outside its range.
    #[error("bad field {field} of paddle {paddle:?}: value {value:#04x} out of range")]
    BadField {
        /// Name of the field.
        field: &'static str,
        /// Paddle index (0..8) the field belongs to, if it is per paddle.
        paddle: Option<u8>,
        /// The offending raw value.
        value: u8,
    },
}

/// Why a report could not be written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum EncodeError {
    /// The output buffer is shorter than the report.
    #[error("buffer too small: need {needed} bytes, have {available}")]
    BufferTooSmall {
        /// Bytes the report needs.
        needed: usize,
        /// Bytes available in the buffer.
        available: usize,
    },
}

/// Checks the length and version byte shared by both report kinds.
pub(crate) fn check_header(bytes: &[u8], expected: usize) -> Result<(), DecodeError> {
    if bytes.len() != expected {
        return Err(DecodeError::WrongLength {
            expected,
            actual: bytes.len(),
        });
    }
    if bytes[0] != crate::FORMAT_VERSION {
        return Err(DecodeError::UnknownVersion {
            found: bytes[0],
            supported: crate::FORMAT_VERSION,
        });
    }
    Ok(())
}

/// Checks an output buffer is at least `needed` bytes long.
pub(crate) fn check_buffer(buf: &[u8], needed: usize) -> Result<(), EncodeError> {
    if buf.len() < needed {
        return Err(EncodeError::BufferTooSmall {
            needed,
            available: buf.len(),
        });
    }
    Ok(())
}
