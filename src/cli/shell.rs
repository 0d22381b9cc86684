//! Shell integration: `contactmap completions SHELL` and `contactmap man`, both generated from the
//! same clap definitions as `--help`.

use std::path::PathBuf;

use clap::{Args, ValueEnum};

use crate::cli::output::Output;
use contactmap::error::{Error, Result};

/// Shells, for `completions`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ShellArg {
    /// bash
    Bash,
    /// zsh
    Zsh,
    /// fish
    Fish,
}

/// Arguments of `contactmap completions`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Prints the completion script for SHELL on standard output.

Install:
  bash:  contactmap completions bash \\
             > ~/.local/share/bash-completion/completions/contactmap
         (or: source <(contactmap completions bash) in ~/.bashrc)
  zsh:   contactmap completions zsh > ~/.zfunc/_contactmap
         (with fpath+=~/.zfunc before compinit)
  fish:  contactmap completions fish \\
             > ~/.config/fish/completions/contactmap.fish")]
pub struct CompletionsArgs {
    /// The shell.
    #[arg(value_enum)]
    pub shell: ShellArg,
}

/// Arguments of `contactmap man`.
#[derive(Debug, Args)]
#[command(after_long_help = "\
Writes one man page per command into DIR: contactmap.1 and contactmap-SUBCOMMAND.1 (nested
subcommands too, e.g. contactmap-plot-map.1). `make man` writes them into target/man.
Read one with: man -l target/man/contactmap-balance.1")]
pub struct ManArgs {
    /// Output folder (created when missing).
    #[arg(long, default_value = "target/man")]
    pub dir: PathBuf,
}

/// Run `contactmap completions` for the command line `command` (the whole of it, from the top).
pub fn run_completions(args: &CompletionsArgs, mut command: clap::Command) -> Result<()> {
    let mut bytes = Vec::new();
    let shell = match args.shell {
        ShellArg::Bash => clap_complete::Shell::Bash,
        ShellArg::Zsh => clap_complete::Shell::Zsh,
        ShellArg::Fish => clap_complete::Shell::Fish,
    };
    clap_complete::generate(shell, &mut command, "contactmap", &mut bytes);
    let mut out = Output::open(None)?;
    out.write_all(&bytes)?;
    out.finish()
}

/// Run `contactmap man` for the command line `command` (the whole of it, from the top).
pub fn run_man(args: &ManArgs, mut command: clap::Command) -> Result<()> {
    std::fs::create_dir_all(&args.dir).map_err(|e| Error::io(&args.dir, e))?;
    command.build();
    let mut written = 0;
    write_pages(&command, "contactmap", args, &mut written)?;
    eprintln!("{written} man pages in {}", args.dir.display());
    Ok(())
}

fn write_pages(
    command: &clap::Command,
    name: &str,
    args: &ManArgs,
    written: &mut usize,
) -> Result<()> {
    let page = command.clone().name(name.to_string());
    let mut bytes = Vec::new();
    clap_mangen::Man::new(page)
        .render(&mut bytes)
        .map_err(|e| Error::io(&args.dir, e))?;
    let path = args.dir.join(format!("{name}.1"));
    let mut out = Output::open(Some(&path))?;
    out.write_all(&bytes)?;
    out.finish()?;
    *written += 1;
    for sub in command.get_subcommands().filter(|s| s.get_name() != "help") {
        write_pages(sub, &format!("{name}-{}", sub.get_name()), args, written)?;
    }
    Ok(())
}
