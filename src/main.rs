//! The `contactmap` command-line tool: a thin layer over the library.
//!
//! Exit codes: 0 on success (including a closed output pipe, as in `contactmap dump ... | head`),
//! 2 on bad input or any other error (a parameter, a corrupt or unsupported file, an I/O error:
//! `contactmap::error::Concern`), with one line on standard error naming the file and the
//! problem; 130 when the work was interrupted.

use std::process::ExitCode;

mod cli;

use clap::error::ErrorKind;

/// A libhdf5 metadata read that never returns (a corrupt file): one line, exit 2.
fn hdf5_timed_out(message: &str) {
    eprintln!("contactmap: error: {message}");
    std::process::exit(2);
}

fn main() -> ExitCode {
    contactmap::io::hdf5_guard::set_timeout_handler(hdf5_timed_out);
    let parsed = match cli::parse(std::env::args_os()) {
        Ok(parsed) => parsed,
        Err(error)
            if matches!(
                error.kind(),
                ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            ) =>
        {
            error.exit()
        }
        Err(error) => {
            eprintln!("contactmap: error: {}", cli::argument_error_line(&error));
            return ExitCode::from(2);
        }
    };
    match cli::run(parsed) {
        Ok(status) => ExitCode::from(status.code()),
        Err(error) if error.is_broken_pipe() => ExitCode::SUCCESS,
        Err(contactmap::Error::Parameter {
            name,
            value,
            expected,
        }) => {
            // A parameter is named as its option.
            let args: Vec<_> = std::env::args_os().collect();
            let option = cli::option_name(&args, name);
            eprintln!("contactmap: error: --{option} {value}: {expected}");
            ExitCode::from(2)
        }
        Err(contactmap::Error::Interrupted) => {
            eprintln!("contactmap: error: interrupted");
            ExitCode::from(130)
        }
        Err(error) => {
            let mut message = error.to_string();
            let mut source = std::error::Error::source(&error);
            while let Some(cause) = source {
                let text = cause.to_string();
                if !message.contains(&text) {
                    message.push_str(": ");
                    message.push_str(&text);
                }
                source = cause.source();
            }
            eprintln!("contactmap: error: {message}");
            ExitCode::from(2)
        }
    }
}
