//! Ctrl-C (SIGINT): long runs check between frames whether the user asked them to
//! stop, finish the frame in hand and return [`Error::Interrupted`]; the command line
//! then exits with status 130 after the device is idle.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::error::{Error, Result};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Routes Ctrl-C to [`requested`] instead of killing the process. A second Ctrl-C
/// while the first is being honoured exits at once with status 130.
pub fn install() {
    // Failing to install (another handler is set) leaves the default behaviour.
    let _ = ctrlc::set_handler(|| {
        if REQUESTED.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
    });
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
