//! Standard output of every command, written through [`outln!`] instead of `println!`.
//!
//! `println!` panics when standard output is closed (`cimax arena | head -3`) or full
//! (`> /dev/full`). Here a failed write is a value, [`StdoutError`], that the commands return
//! with `?`; `main` turns it into the conventional ending ([`StdoutError::exit_code`]): quiet
//! success for a closed pipe, as `cat` and `grep` do, else `cannot write standard output: …`
//! and exit 1.

use std::fmt;
use std::io::{self, Write};
use std::process::ExitCode;

/// Writing standard output failed (a closed pipe, a full disk).
#[derive(Debug)]
pub struct StdoutError(pub io::Error);

impl fmt::Display for StdoutError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "cannot write standard output: {}", io_reason(&self.0))
    }
}

impl std::error::Error for StdoutError {}

impl StdoutError {
    /// The process's ending for this error: quiet success if the reader went away (a broken
    /// pipe: nobody reads the rest, as with `cat`), else the message on stderr and exit 1.
    pub fn exit_code(&self) -> ExitCode {
        if self.0.kind() == io::ErrorKind::BrokenPipe {
            ExitCode::SUCCESS
        } else {
            eprintln!("cimax: {self}");
            ExitCode::FAILURE
        }
    }
}

/// Why a command stopped: a bad option, input or output path (exit 2, the message on stderr),
/// or standard output that cannot be written ([`StdoutError::exit_code`]).
#[derive(Debug)]
pub enum Fail {
    /// A usage, input or set-up error: the message, without the command's name.
    Input(String),
    /// Standard output cannot be written.
    Stdout(StdoutError),
}

impl From<String> for Fail {
    fn from(e: String) -> Self {
        Fail::Input(e)
    }
}

impl From<&str> for Fail {
    fn from(e: &str) -> Self {
        Fail::Input(e.to_string())
    }
}

impl From<StdoutError> for Fail {
    fn from(e: StdoutError) -> Self {
        Fail::Stdout(e)
    }
}

impl From<Box<dyn std::error::Error + Send + Sync>> for Fail {
    /// A [`StdoutError`] stays one; any other error is an input error, by its message.
    fn from(e: Box<dyn std::error::Error + Send + Sync>) -> Self {
        match e.downcast::<StdoutError>() {
            Ok(e) => Fail::Stdout(*e),
            Err(e) => Fail::Input(e.to_string()),
        }
    }
}

/// What a command ends with: its exit code, or why it stopped.
pub type Exit = Result<ExitCode, Fail>;

/// The process's exit code for `r` of command `cmd` (`cimax arena`): a [`Fail::Input`] is
/// printed as `CMD: MESSAGE` and exits 2.
pub fn finish(cmd: &str, r: Exit) -> ExitCode {
    match r {
        Ok(code) => code,
        Err(Fail::Input(e)) => {
            eprintln!("{cmd}: {e}");
            ExitCode::from(2)
        }
        Err(Fail::Stdout(e)) => e.exit_code(),
    }
}

/// An I/O error's reason without the ` (os error N)` the standard library appends: `No space
/// left on device`.
pub fn io_reason(e: &io::Error) -> String {
    let s = e.to_string();
    match s.rfind(" (os error ") {
        Some(i) if s.ends_with(')') => s[..i].to_string(),
        _ => s,
    }
}

/// Writes `args` and a newline to standard output, flushed.
///
/// # Errors
/// If standard output cannot be written.
pub fn line(args: fmt::Arguments<'_>) -> Result<(), StdoutError> {
    let mut out = io::stdout().lock();
    out.write_fmt(args)
        .and_then(|()| out.write_all(b"\n"))
        .and_then(|()| out.flush())
        .map_err(StdoutError)
}

/// Writes `s` to standard output as it is (no newline added), flushed.
///
/// # Errors
/// If standard output cannot be written.
pub fn text(s: &str) -> Result<(), StdoutError> {
    let mut out = io::stdout().lock();
    out.write_all(s.as_bytes())
        .and_then(|()| out.flush())
        .map_err(StdoutError)
}

/// `println!` that returns `Result<(), StdoutError>` instead of panicking.
macro_rules! outln {
    ($($arg:tt)*) => {
        $crate::cli::out::line(format_args!($($arg)*))
    };
}
pub(crate) use outln;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reason_drops_the_os_error_number() {
        let e = io::Error::from_raw_os_error(28);
        assert_eq!(
            StdoutError(e).to_string(),
            "cannot write standard output: No space left on device"
        );
        let e = io::Error::other("odd");
        assert_eq!(io_reason(&e), "odd");
    }
}
