//! Ctrl-C (SIGINT): long runs check between frames whether the user asked them to
//! stop, finish the frame in hand and return [`Error::Interrupted`]; the command line
//! then exits with status 130 after the device is idle. The application routes the
//! signal here ([`request`]).

use std::sync::atomic::{AtomicBool, Ordering};

use crate::error::{Error, Result};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Asks long runs to stop; returns whether they were asked already (a second Ctrl-C
/// while the first is being honoured exits at once).
pub fn request() -> bool {
    REQUESTED.swap(true, Ordering::SeqCst)
}

/// Whether Ctrl-C was pressed.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::SeqCst)
}

/// `Err(Error::Interrupted)` once Ctrl-C was pressed: call between units of work.
pub fn check() -> Result<()> {
    if requested() {
        Err(Error::Interrupted)
    } else {
        Ok(())
    }
}
