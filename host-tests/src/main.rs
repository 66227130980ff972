//! `lensray`: the host simulator. `lensray --help` lists the commands,
//! `lensray COMMAND --help` their options.
//!
//! Exit status: 0 on success (and for `--help`, `--version`), 2 on any error
//! (bad scene, bad arguments, unwritable output). Errors are one line on
//! stderr: a scene error reads `SCENE:LINE: message` (as compilers print, for
//! editors to jump to), any other `lensray: message`.

use std::process::ExitCode;

use clap::error::{ContextKind, ContextValue, ErrorKind};
use clap::{CommandFactory, Parser, Subcommand};

/// The commands, one file each, and the options they share.
mod cli {
    pub(crate) mod bake;
    pub(crate) mod compare;
    pub(crate) mod emulate;
    pub(crate) mod emulate_pico;
    pub(crate) mod opts;
    pub(crate) mod render;
    pub(crate) mod sheet;
}

/// lensray's host simulator: renders scene files in Q16.16 or f32, compares
/// the two, lays renders out on a sheet, bakes scenes for firmware and runs
/// the firmware under emulators.
#[derive(Parser, Debug)]
#[command(
    name = "lensray",
    version,
    arg_required_else_help = true,
    after_help = "Exit status: 0 on success, 2 on any error. Errors are one line on stderr: \
                  SCENE:LINE: message for a scene's, lensray: message for any other."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// Each command, with the options it takes. A repeated option takes its last
/// value; numbers may be written negative, to get the range message.
#[derive(Subcommand, Debug)]
enum Command {
    #[command(args_override_self = true, allow_negative_numbers = true)]
    Render(cli::render::RenderArgs),
    #[command(args_override_self = true, allow_negative_numbers = true)]
    Sheet(cli::sheet::SheetArgs),
    #[command(args_override_self = true, allow_negative_numbers = true)]
    Emulate(cli::emulate::EmulateArgs),
    #[command(args_override_self = true, allow_negative_numbers = true)]
    Compare(cli::compare::CompareArgs),
    #[command(args_override_self = true, allow_negative_numbers = true)]
    Bake(cli::bake::BakeArgs),
}

/// A one-line error for the user; exit status 2.
pub(crate) struct Fail(pub(crate) String);

impl<T: std::fmt::Display> From<T> for Fail {
    fn from(e: T) -> Self {
        Fail(e.to_string())
    }
}

fn main() -> ExitCode {
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    let cli = match Cli::try_parse_from(&args) {
        Ok(cli) => cli,
        Err(e) if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) => {
            // Asked for: help or the version on stdout, success.
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            let _ = e.print();
            return ExitCode::from(2);
        }
        Err(e) => {
            // The command the error is about, if the first argument names one.
            let first = args.get(1).and_then(|a| a.to_str()).unwrap_or_default();
            let known = Cli::command().get_subcommands().any(|c| c.get_name() == first);
            return fail(&Fail(usage_error(&e, if known { first } else { "" })));
        }
    };
    let result = match cli.command {
        Command::Render(a) => cli::render::run(a),
        Command::Sheet(a) => cli::sheet::run(a),
        Command::Emulate(a) => cli::emulate::run(a),
        Command::Compare(a) => cli::compare::run(a),
        Command::Bake(a) => cli::bake::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => fail(&e),
    }
}

/// Prints the error (with the program's name unless it names a line); status 2.
fn fail(Fail(msg): &Fail) -> ExitCode {
    if names_a_line(msg) {
        eprintln!("{msg}");
    } else {
        eprintln!("lensray: {msg}");
    }
    ExitCode::from(2)
}

/// Whether a message starts `FILE:LINE: `: printed without the program's
/// name, so that editors and IDEs can jump to the line.
fn names_a_line(msg: &str) -> bool {
    let Some((head, _)) = msg.split_once(": ") else {
        return false;
    };
    head.rsplit_once(':')
        .is_some_and(|(file, line)| !file.is_empty() && !line.is_empty() && line.bytes().all(|b| b.is_ascii_digit()))
}

/// What a command takes besides its options, for a wrong count of them.
fn takes(command: &str) -> &'static str {
    match command {
        "sheet" => "one or more scene files",
        "compare" => "one scene file or two images",
        _ => "one scene file",
    }
}

/// clap's error as one line in lensray's words: `--width abc: not a whole
/// number`, `--width needs a value`, `unknown option "--widht"; did you mean
/// "--width"?`. `command` is the command it is about ("" for none).
fn usage_error(e: &clap::Error, command: &str) -> String {
    let text = |kind| match e.get(kind) {
        Some(ContextValue::String(s)) => Some(s.clone()),
        Some(ContextValue::Strings(v)) => Some(v.join(", ")),
        _ => None,
    };
    let list = |kind| match e.get(kind) {
        Some(ContextValue::Strings(v)) => v.clone(),
        _ => Vec::new(),
    };
    // "--width <W>" -> "--width": the flag as the user typed it.
    let flag = text(ContextKind::InvalidArg)
        .map(|a| a.split([' ', '=']).next().unwrap_or_default().to_string())
        .unwrap_or_default();
    let hint = |suggested: Option<String>| suggested.map_or_else(String::new, |s| format!("; did you mean \"{s}\"?"));
    let help = if command.is_empty() {
        "; see lensray --help".to_string()
    } else {
        format!("; see lensray {command} --help")
    };
    match e.kind() {
        ErrorKind::ValueValidation => {
            let value = text(ContextKind::InvalidValue).unwrap_or_default();
            let why = std::error::Error::source(e).map_or_else(|| "not valid".to_string(), |s| s.to_string());
            format!("{flag} {value}: {why}")
        }
        ErrorKind::InvalidValue => {
            let value = text(ContextKind::InvalidValue).unwrap_or_default();
            let valid = or_list(&list(ContextKind::ValidValue));
            match (value.is_empty(), valid.is_empty()) {
                (true, true) => format!("{flag} needs a value"),
                (true, false) => format!("{flag} needs a value: {valid}"),
                (false, _) => format!("{flag} {value}: must be {valid}"),
            }
        }
        ErrorKind::UnknownArgument => {
            let arg = text(ContextKind::InvalidArg).unwrap_or_default();
            if arg.starts_with('-') && arg.len() > 1 {
                format!(
                    "unknown option \"{arg}\"{}{help}",
                    hint(text(ContextKind::SuggestedArg))
                )
            } else {
                format!("{command} takes {}: \"{arg}\" is one too many", takes(command))
            }
        }
        ErrorKind::InvalidSubcommand => format!(
            "unknown command \"{}\"{}{help}",
            text(ContextKind::InvalidSubcommand).unwrap_or_default(),
            hint(text(ContextKind::SuggestedSubcommand))
        ),
        ErrorKind::MissingRequiredArgument => {
            let missing = list(ContextKind::InvalidArg);
            match missing.iter().find(|a| a.starts_with('-')) {
                Some(option) => format!("{command} needs {option}{help}"),
                None => format!("{command} takes {}{help}", takes(command)),
            }
        }
        // Anything else: clap's own first line, without its "error: ".
        _ => {
            let rendered = e.render().to_string();
            let first = rendered.lines().next().unwrap_or_default();
            first.strip_prefix("error: ").unwrap_or(first).to_string()
        }
    }
}

/// "a, b or c".
fn or_list(items: &[String]) -> String {
    match items.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => items.join(""),
    }
}
