//! Stopping long work from outside: a host that runs the library (the Python binding, on
//! Ctrl-C) asks with [`request`]; the streaming loops ([`crate::io::read_ahead`], hence every
//! read of a cooler's pixels) and the balancing iterations see it at their next block or
//! iteration and return the error `interrupted`. The request holds
//! for the whole process until [`clear`]: every piece of work under way stops.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::error::{Error, Result};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Ask every piece of work under way to stop at its next check.
pub fn request() {
    REQUESTED.store(true, Ordering::SeqCst);
}

/// Withdraw the request (once the interrupted work has returned).
pub fn clear() {
    REQUESTED.store(false, Ordering::SeqCst);
}

/// Whether a stop was asked for.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// `Err("interrupted")` when a stop was asked for.
///
/// ```
/// use contactmap::interrupt;
///
/// assert!(interrupt::check().is_ok());
/// interrupt::request();
/// assert_eq!(interrupt::check().unwrap_err().to_string(), "interrupted");
/// interrupt::clear();
/// assert!(interrupt::check().is_ok());
/// ```
pub fn check() -> Result<()> {
    if requested() {
        Err(Error::Interrupted)
    } else {
        Ok(())
    }
}
