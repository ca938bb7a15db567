//! The two terminal streams, used as a Unix filter uses them (issue #52).
//!
//! Standard output carries a command's result: `outln!` and `out!` write and flush it and
//! return the error instead of panicking. A closed pipe (`| head -1`, `| true`) is the end
//! of the output, which `cli::exit_code` turns into a quiet success, as `cat` and `rg`
//! treat it; any other failure (`> /dev/full`) is an I/O error naming standard output
//! (exit 4).
//!
//! Standard error carries notes and progress: `errln!` writes and ignores a failure, so a
//! closed pipe or a hung-up terminal (a dropped SSH session) can never stop or crash a run.

use std::fmt;
use std::io::{self, Write as _};

/// A failed write to standard output.
#[derive(Debug)]
pub struct StdoutError(pub io::Error);

impl StdoutError {
    /// The reader went away (a closed pipe): the output ends there, not an error.
    pub fn closed(&self) -> bool {
        self.0.kind() == io::ErrorKind::BrokenPipe
    }
}

impl fmt::Display for StdoutError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "cannot write to standard output: {}", self.0)
    }
}

impl std::error::Error for StdoutError {}

/// Write `args` to standard output and flush it (a full device fails here, not at exit).
pub fn out(args: fmt::Arguments) -> Result<(), StdoutError> {
    let mut s = io::stdout().lock();
    s.write_fmt(args)
        .and_then(|()| s.flush())
        .map_err(StdoutError)
}

/// Write `args` to standard error; a failure is ignored (see the module docs).
pub fn err(args: fmt::Arguments) {
    let _ = io::stderr().lock().write_fmt(args);
}

/// `println!` to standard output, returning `Result<(), StdoutError>`.
#[macro_export]
macro_rules! outln {
    () => { $crate::term::out(format_args!("\n")) };
    ($($a:tt)*) => { $crate::term::out(format_args!("{}\n", format_args!($($a)*))) };
}

/// `print!` to standard output, returning `Result<(), StdoutError>`.
#[macro_export]
macro_rules! out {
    ($($a:tt)*) => { $crate::term::out(format_args!($($a)*)) };
}

/// `eprintln!` that never panics (a closed or hung-up standard error is ignored).
#[macro_export]
macro_rules! errln {
    ($($a:tt)*) => { $crate::term::err(format_args!("{}\n", format_args!($($a)*))) };
}
