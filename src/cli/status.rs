//! How a command that succeeded ended, and its exit code.

/// How a command that succeeded ended: `validate` ends with [`Status::Invalid`] (exit code 1)
/// when it checked the file and found it invalid; every other command with
/// [`Status::Success`] (exit code 0). Errors are exit code 2 (`main`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    /// Exit code 0.
    Success,
    /// Exit code 1: the file checked is invalid.
    Invalid,
}

impl Status {
    /// The process exit code.
    pub fn code(self) -> u8 {
        match self {
            Status::Success => 0,
            Status::Invalid => 1,
        }
    }
}
