//! Warnings and notes gathered while a command runs, printed only once it has succeeded.
//!
//! A command that fails prints one line, its error; a warning printed earlier ("chrM shorter
//! than the window") would read as the cause of a failure it has nothing to do with. Commands
//! therefore push their warnings (and progress notes such as per-window boundary counts) into a
//! [`Warnings`] list as they go, and print it after their outputs are complete. Readers that
//! gather their own warnings hand them over with [`Warnings::extend`].

use std::io::Write;

/// Messages for standard error, held back until the command succeeds.
#[derive(Debug, Default)]
pub struct Warnings {
    /// `(is_warning, message)` in the order they were pushed.
    messages: Vec<(bool, String)>,
}

impl Warnings {
    /// An empty list.
    pub fn new() -> Self {
        Self::default()
    }

    /// Add a warning, printed as `contactmap: warning: MESSAGE`.
    pub fn push(&mut self, message: impl Into<String>) {
        self.messages.push((true, message.into()));
    }

    /// Add several warnings (a reader's own, for instance), in order.
    pub fn extend<I: IntoIterator<Item = S>, S: Into<String>>(&mut self, messages: I) {
        self.messages
            .extend(messages.into_iter().map(|m| (true, m.into())));
    }

    /// Add a note (not a warning), printed as `contactmap: MESSAGE`.
    pub fn note(&mut self, message: impl Into<String>) {
        self.messages.push((false, message.into()));
    }

    /// The lines that [`Warnings::print`] writes, in order, each without its newline.
    pub fn lines(&self) -> Vec<String> {
        self.messages
            .iter()
            .map(|(is_warning, message)| {
                let kind = if *is_warning { "warning: " } else { "" };
                format!("contactmap: {kind}{message}")
            })
            .collect()
    }

    /// Print every message on standard error, one line each; call once the command succeeded.
    /// A standard error that cannot be written is ignored, as with `eprintln!` in a closed pipe.
    pub fn print(self) {
        let mut stderr = std::io::stderr().lock();
        for line in self.lines() {
            if writeln!(stderr, "{line}").is_err() {
                return;
            }
        }
    }
}

/// Print a reader's own warnings (the `.hic` records it dropped, for instance) as warnings; for
/// commands that have no other warning to hold back. Call it once the command succeeded.
pub fn print_reader_warnings(messages: Vec<String>) {
    let mut warnings = Warnings::new();
    warnings.extend(messages);
    warnings.print();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_keep_order_and_kind() {
        let mut warnings = Warnings::new();
        assert!(warnings.lines().is_empty());
        warnings.push("chrM shorter than the window");
        warnings.note("window 100000: 3 boundaries");
        warnings.extend(["a", "b"]);
        assert_eq!(
            warnings.lines(),
            vec![
                "contactmap: warning: chrM shorter than the window",
                "contactmap: window 100000: 3 boundaries",
                "contactmap: warning: a",
                "contactmap: warning: b",
            ]
        );
    }
}
