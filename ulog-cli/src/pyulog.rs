//! pyulog's command-line habits, so that a pyulog user's command works: ulog2csv's
//! single-dash long flags (`-ts`, `-te`), and the `--ignore` flag every pyulog script
//! takes.

use std::ffi::OsString;

/// The help of `-i/--ignore` (`--ignore` of `params`, `-x/--ignore` of `gps-dump`).
pub const IGNORE_HELP: &str = "Accepted for pyulog's scripts (ignore string parsing exceptions): \
text that is not UTF-8 never stops this reader (it is kept and shown with U+FFFD)";

/// ulog2csv's flags of one dash and two letters, which a parser of one-letter short
/// flags reads as `-t` followed by `s`: the long option each means.
const CSV_FLAGS: [(&str, &str); 2] = [("-ts", "--time-start"), ("-te", "--time-end")];

/// The command line with ulog2csv's `-ts`/`-te` (also `-ts=N`) after the `csv`
/// subcommand written as `--time-start`/`--time-end`; anything else, and whatever
/// follows `--`, as it was.
pub fn rewrite_args(args: impl IntoIterator<Item = OsString>) -> Vec<OsString> {
    let mut args: Vec<OsString> = args.into_iter().collect();
    // The subcommand: the first argument after the program's name that is not an
    // option (the global options take no values).
    let command = args
        .iter()
        .skip(1)
        .position(|a| !a.to_string_lossy().starts_with('-'))
        .map(|i| i + 1);
    let Some(command) = command.filter(|&i| args[i] == "csv") else {
        return args;
    };
    for arg in &mut args[command + 1..] {
        let Some(text) = arg.to_str() else {
            continue;
        };
        if text == "--" {
            break;
        }
        let long = CSV_FLAGS
            .iter()
            .find_map(|(short, long)| match text.strip_prefix(short) {
                Some("") => Some((*long).to_owned()),
                Some(rest) => rest
                    .strip_prefix('=')
                    .map(|value| format!("{long}={value}")),
                None => None,
            });
        if let Some(long) = long {
            *arg = long.into();
        }
    }
    args
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rewrite(args: &[&str]) -> Vec<String> {
        rewrite_args(args.iter().map(OsString::from))
            .into_iter()
            .map(|a| a.into_string().unwrap())
            .collect()
    }

    #[test]
    fn csv_takes_ulog2csv_time_flags() {
        assert_eq!(
            rewrite(&["ulog", "csv", "f.ulg", "-ts", "5", "-te=9", "-d", ";"]),
            [
                "ulog",
                "csv",
                "f.ulg",
                "--time-start",
                "5",
                "--time-end=9",
                "-d",
                ";"
            ]
        );
        assert_eq!(
            rewrite(&["ulog", "-q", "csv", "f.ulg", "-ts", "5"]),
            ["ulog", "-q", "csv", "f.ulg", "--time-start", "5"]
        );
        // After `--` an argument is a file, and other commands are left alone.
        assert_eq!(
            rewrite(&["ulog", "csv", "-m", "a", "--", "-ts"]),
            ["ulog", "csv", "-m", "a", "--", "-ts"]
        );
        assert_eq!(
            rewrite(&["ulog", "plot", "f.ulg", "-ts"]),
            ["ulog", "plot", "f.ulg", "-ts"]
        );
        assert_eq!(rewrite(&["ulog", "csv", "-tsx"]), ["ulog", "csv", "-tsx"]);
    }
}
