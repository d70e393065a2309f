//! Renders into memory: a command (`lgh explosion`, `lgh gi`) run from a library — the Python
//! package's `render_explosion` and `render_gi` — with the command's own flags, defaults and
//! checks, its image returned instead of written. What the commands share: the parse of a
//! command line without the flags of files, the list of settings a caller may give (for
//! stubs and docstrings), and the error's stage.

use clap::{ArgMatches, Args, FromArgMatches};

/// Why a render into memory failed: its command line, settings or input files were refused
/// before any work (the caller's to mend), or the render itself failed.
#[derive(Debug)]
pub enum InMemoryError {
    /// Refused before any work: a flag the parser refused ([`Usage`](crate::Usage)), a setting,
    /// a missing input file ([`MissingFile`](crate::files::MissingFile)).
    Refused(crate::Error),
    /// The render's own error (a grid the file lacks, a frame that cannot be read).
    Failed(crate::Error),
}

impl InMemoryError {
    /// The error, whichever its stage.
    #[must_use]
    pub fn error(&self) -> &crate::Error {
        match self {
            InMemoryError::Refused(e) | InMemoryError::Failed(e) => e,
        }
    }
}

/// A setting of a command that a render into memory takes: what the Python package takes as a
/// keyword argument, its stubs and docstrings list.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Setting {
    /// The flag's long name (`scatter-depth`).
    pub flag: String,
    /// Whether it takes a value (`--albedo 0.7`) or is a switch (`--no-domain-offset`).
    pub takes_value: bool,
    /// Its default as the command shows it, if it has one.
    pub default: Option<String>,
    /// The values it accepts, where they are a fixed list.
    pub choices: Vec<String>,
    /// The help's first sentence.
    pub help: String,
}

/// The command of the arguments `A`, named `name`.
fn command<A: Args>(name: &'static str) -> clap::Command {
    A::augment_args(clap::Command::new(name))
}

/// Every setting of the command of `A` but the flags `input` (the positional input the
/// caller passes apart, e.g. `vdb`) and `files`, in the command's order.
#[must_use]
pub fn settings<A: Args>(input: &str, files: &[&str]) -> Vec<Setting> {
    command::<A>("settings")
        .get_arguments()
        .filter(|a| {
            let id = a.get_id().as_str();
            id != input && !files.contains(&id)
        })
        .filter_map(|a| {
            let flag = a.get_long()?.to_string();
            let takes_value = a.get_action().takes_values();
            let default = a
                .get_default_values()
                .iter()
                .map(|v| v.to_string_lossy().into_owned())
                .reduce(|a, b| format!("{a},{b}"));
            let choices = a
                .get_possible_values()
                .iter()
                .map(|v| v.get_name().to_string())
                .collect();
            let help = a.get_help().map(ToString::to_string).unwrap_or_default();
            Some(Setting {
                flag,
                takes_value,
                default,
                choices,
                help: first_sentence(&help).to_string(),
            })
        })
        .collect()
}

/// The flags of `matches` given on the command line, except those named in `except`.
pub(crate) fn given_flags<A: Args>(matches: &ArgMatches, except: &[&str]) -> Vec<clap::Arg> {
    command::<A>("given")
        .get_arguments()
        .filter(|a| {
            let id = a.get_id().as_str();
            !except.contains(&id)
                && matches.value_source(id) == Some(clap::parser::ValueSource::CommandLine)
        })
        .cloned()
        .collect()
}

/// The command line `args` of a render into memory with `A`'s flags, `out` no longer
/// required and the flags of `files` refused (a render into memory writes none).
pub(crate) fn parse<A, I, T>(
    name: &'static str,
    args: I,
    files: &[&str],
) -> Result<(A, ArgMatches), crate::Error>
where
    A: Args + FromArgMatches,
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let command = command::<A>(name).no_binary_name(true).mut_arg("out", |a| {
        a.required(false)
            .required_unless_present(clap::builder::Resettable::<clap::Id>::Reset)
    });
    let matches = command
        .try_get_matches_from(args)
        .map_err(|e| crate::usage(e.render().to_string().trim().to_string()))?;
    let file_flag = given_flags::<A>(&matches, &[])
        .into_iter()
        .find(|a| files.contains(&a.get_id().as_str()));
    if let Some(arg) = file_flag {
        return Err(crate::usage(format!(
            "--{}: a render into memory writes no files",
            arg.get_long().unwrap_or("?")
        )));
    }
    let args = A::from_arg_matches(&matches)
        .map_err(|e| crate::usage(e.render().to_string().trim().to_string()))?;
    Ok((args, matches))
}

/// `text`'s first sentence, without its full stop: up to the first `. ` before a capital that
/// does not end an abbreviation (`e.g.`, `Sec.`, `eq.`).
pub(crate) fn first_sentence(text: &str) -> &str {
    const ABBREVIATIONS: [&str; 6] = ["e.g", "i.e", "Sec", "eq", "Eq", "Fig"];
    let end = text.match_indices(". ").map(|(i, _)| i).find(|&i| {
        let next = text[i + 2..].chars().next();
        let word = text[..i].rsplit([' ', '(']).next().unwrap_or_default();
        next.is_some_and(|c| c.is_uppercase() || c == '`') && !ABBREVIATIONS.contains(&word)
    });
    end.map_or(text, |i| &text[..i]).trim_end_matches('.')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_sentence_skips_abbreviations() {
        assert_eq!(
            first_sentence("Frames (e.g. 50..56). One each."),
            "Frames (e.g. 50..56)"
        );
        assert_eq!(
            first_sentence("Pruning (paper Sec. 6.3). More."),
            "Pruning (paper Sec. 6.3)"
        );
        assert_eq!(first_sentence("No stop at all"), "No stop at all");
    }
}
