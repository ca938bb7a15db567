//! Stopping a run cleanly on SIGINT (Ctrl-C), SIGTERM and SIGHUP: the first signal raises
//! a flag that the run driver reads after each batch (at most `step::MAX_BATCH` steps), so
//! the run writes the state it reached as a last frame and a `summary.json` that says
//! `"interrupted"`, and the binary exits with `EXIT_INTERRUPTED`; a second signal exits at
//! once. Only the `run` command installs the handlers (`install`); library callers and tests
//! raise their own flag (`RunOptions::interrupt`).

use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};

/// Raised by the first signal.
static REQUESTED: AtomicBool = AtomicBool::new(false);
/// The signal that raised it (0: none).
static SIGNAL: AtomicI32 = AtomicI32::new(0);

/// The exit status of a run stopped by a signal (128 + SIGINT, the shell's convention for
/// Ctrl-C; whatever the signal, so scripts test one number).
pub const EXIT_INTERRUPTED: u8 = 130;

/// Install the handlers; returns the flag they raise, for `RunOptions::interrupt`.
#[cfg(unix)]
pub fn install() -> &'static AtomicBool {
    extern "C" fn on_signal(sig: libc::c_int) {
        // Only async-signal-safe work here: atomics and _exit.
        if REQUESTED.swap(true, Ordering::SeqCst) {
            // SAFETY: _exit is async-signal-safe; a second signal asks to stop now.
            unsafe { libc::_exit(EXIT_INTERRUPTED as libc::c_int) };
        }
        SIGNAL.store(sig, Ordering::SeqCst);
    }
    for sig in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
        // SAFETY: `on_signal` has the handler's C signature and touches only atomics and
        // _exit; the zeroed sigaction is valid (empty mask, no flags) before its fields
        // are set.
        unsafe {
            let mut action: libc::sigaction = std::mem::zeroed();
            action.sa_sigaction = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
            libc::sigemptyset(&mut action.sa_mask);
            libc::sigaction(sig, &action, std::ptr::null_mut());
        }
    }
    &REQUESTED
}

/// Without unix signals the flag is never raised (Ctrl-C ends the process as before).
#[cfg(not(unix))]
pub fn install() -> &'static AtomicBool {
    &REQUESTED
}

/// The name of the signal that raised the installed flag ("signal" when a caller raised
/// its own flag).
pub fn signal_name() -> &'static str {
    #[cfg(unix)]
    match SIGNAL.load(Ordering::SeqCst) {
        libc::SIGINT => return "SIGINT",
        libc::SIGTERM => return "SIGTERM",
        libc::SIGHUP => return "SIGHUP",
        _ => {}
    }
    "an interrupt request"
}
