//! Checks, made before any work starts, that an output path can be written:
//! its folder exists, it is not a folder, and — for outputs that are never
//! overwritten — nothing is there yet; that no two outputs of a command are
//! one file; and that no output is a file the command reads (its scenario,
//! its config, the settings, the calibration). [`check_outputs`] makes them
//! all, for every command that writes.

use std::path::{Path, PathBuf};

use super::create_temporary;
use crate::input::node_kind;

/// An output path that cannot be used, named with the option that gave it.
#[derive(Debug, thiserror::Error)]
#[error("{flag} {}{problem}", path.display())]
pub struct OutputError {
    /// The command-line option (or field) that named the path.
    pub flag: String,
    /// The path.
    pub path: PathBuf,
    /// What is wrong with it.
    pub problem: OutputProblem,
}

/// What is wrong with an output path.
#[derive(Debug, thiserror::Error)]
pub enum OutputProblem {
    /// The folder it would go into does not exist.
    #[error(": folder {} does not exist", .0.display())]
    FolderMissing(PathBuf),
    /// It is a folder, or names one (ends in `/`).
    #[error(": is a directory; give a file name")]
    IsDirectory,
    /// Something other than a regular file is there (a FIFO, a device, a
    /// symbolic link), which outputs neither replace nor write through.
    #[error(": is {0}; outputs replace regular files only")]
    NotRegular(&'static str),
    /// Something other than a folder is where a folder should be.
    #[error(": is {0}; give a folder")]
    NotAFolder(&'static str),
    /// Its "folder" is a file.
    #[error(": {} is not a folder", .0.display())]
    FolderNotAFolder(PathBuf),
    /// The path cannot be looked at (a name too long, a file on the way).
    #[error(": {0}")]
    Unusable(std::io::Error),
    /// Another output of the same command is this file.
    #[error(": {0} names the same file")]
    SameAs(String),
    /// Its folder exists but no file can be made in it.
    #[error(": cannot write in folder {}: {}", .0.display(), why_unwritable(.1))]
    FolderUnwritable(PathBuf, std::io::Error),
    /// Something is there, and this output never overwrites; the text says
    /// what to do instead.
    #[error(" exists already; {0}")]
    Exists(&'static str),
    /// It does not end in the extension its format needs.
    #[error(": must be a .{0} file")]
    Extension(&'static str),
    /// Two outputs of one command would be this one file.
    #[error(": the {0} would be written there too; give the results another name (e.g. results.csv)")]
    Shared(&'static str),
    /// It is a file the command reads (what, in words): writing it would
    /// replace the command's own input.
    #[error(": is {0} this command reads; an output never replaces an input, give it another name")]
    IsInput(String),
}

/// Why no file can be made in a folder that exists, in words: a virtual
/// file system (`/proc`, `/sys`) answers "No such file or directory",
/// which would read as if the folder were missing.
fn why_unwritable(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => {
            format!(
                "the folder exists, but its file system makes no new files ({e}); a system folder such as /proc or /sys holds no outputs"
            )
        }
        std::io::ErrorKind::ReadOnlyFilesystem => format!("its file system is read-only ({e})"),
        std::io::ErrorKind::PermissionDenied => format!("no permission to make files there ({e})"),
        _ => e.to_string(),
    }
}

/// What an output does with a file already at its path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Existing {
    /// A regular file there is replaced ([`check_replaceable`]).
    Replaced,
    /// Anything there is refused ([`check_new`]); the text says what to do
    /// instead.
    Refused(&'static str),
}

/// One output of a command: the option (or field) that names it, its path,
/// and what it does with a file there.
#[derive(Clone, Copy, Debug)]
pub struct Output<'a> {
    /// The option that named the path.
    pub flag: &'a str,
    /// The path.
    pub path: &'a Path,
    /// Whether a file there is replaced.
    pub existing: Existing,
}

impl<'a> Output<'a> {
    /// An output that replaces a regular file at `path`.
    pub fn replacing(flag: &'a str, path: &'a Path) -> Self {
        Self {
            flag,
            path,
            existing: Existing::Replaced,
        }
    }

    /// An output that never overwrites: `advice` says what to do if
    /// something is at `path`.
    pub fn new_only(flag: &'a str, path: &'a Path, advice: &'static str) -> Self {
        Self {
            flag,
            path,
            existing: Existing::Refused(advice),
        }
    }
}

/// Every check of a command's outputs, before any work: none is one of the
/// files the command reads, `inputs` (what each is, in words — "the
/// scenario" — and its path; see [`check_not_inputs`]); each can be written
/// ([`check_replaceable`], or [`check_new`] for outputs that never
/// overwrite); and no two are one file ([`check_distinct`]).
pub fn check_outputs(outputs: &[Output<'_>], inputs: &[(&str, &Path)]) -> Result<(), OutputError> {
    let named: Vec<(&str, &Path)> = outputs.iter().map(|o| (o.flag, o.path)).collect();
    check_not_inputs(&named, inputs)?;
    for output in outputs {
        match output.existing {
            Existing::Replaced => check_replaceable(output.flag, output.path)?,
            Existing::Refused(advice) => check_new(output.flag, output.path, advice)?,
        }
    }
    check_distinct(&named)
}

/// Checks that none of `outputs` (option and path) is one of `inputs`
/// (what it is, in words, and path): an output written there would replace
/// what the command was given — a dump over the scenario being run.
/// Compared as files (see [`same_file`]): a relative path and an absolute
/// one, a path through a link, and a hard link all name the file they
/// reach.
pub fn check_not_inputs(outputs: &[(&str, &Path)], inputs: &[(&str, &Path)]) -> Result<(), OutputError> {
    for (flag, path) in outputs {
        if let Some((what, _)) = inputs.iter().find(|(_, input)| same_file(path, input)) {
            return Err(problem(flag, path, OutputProblem::IsInput((*what).to_owned())));
        }
    }
    Ok(())
}

/// Whether `a` and `b` are one file: the same device and inode where both
/// exist (on Unix), else the same path once resolved — links and `..`
/// followed, made absolute from the working folder (a missing file by its
/// folder, resolved, and its name).
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
        use std::os::unix::fs::MetadataExt;
        return (x.dev(), x.ino()) == (y.dev(), y.ino());
    }
    resolved(a) == resolved(b)
}

/// `path` made absolute, its links and `..` followed as far as it exists.
fn resolved(path: &Path) -> PathBuf {
    if let Ok(full) = std::fs::canonicalize(path) {
        return full;
    }
    let folder = path
        .parent()
        .filter(|f| !f.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let folder = std::fs::canonicalize(folder)
        .or_else(|_| std::path::absolute(folder))
        .unwrap_or_else(|_| folder.to_owned());
    folder.join(path.file_name().unwrap_or_default())
}

fn problem(flag: &str, path: &Path, problem: OutputProblem) -> OutputError {
    OutputError {
        flag: flag.to_owned(),
        path: path.to_owned(),
        problem,
    }
}

/// Checks that `path` (given as `flag`) can be written, replacing any
/// regular file there: it does not name a folder, nothing but a regular
/// file is there, and a file can be made in its folder.
///
/// Only regular files are replaced: a FIFO, a device or a symbolic link is
/// refused rather than written through or replaced (writing "over"
/// `/dev/null` as root would otherwise replace the system's `/dev/null`
/// with a file).
pub fn check_replaceable(flag: &str, path: &Path) -> Result<(), OutputError> {
    let fail = |p| Err(problem(flag, path, p));
    let text = path.as_os_str().to_string_lossy();
    let names_a_folder = text.ends_with(std::path::MAIN_SEPARATOR) || text.ends_with('/');
    if path.is_dir() || names_a_folder || path.file_name().is_none() {
        return fail(OutputProblem::IsDirectory);
    }
    let looked = path.symlink_metadata();
    if let Ok(metadata) = &looked
        && !metadata.is_file()
    {
        return fail(OutputProblem::NotRegular(node_kind(metadata.file_type())));
    }
    let folder = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if !folder.is_dir() {
        return fail(if folder.exists() {
            OutputProblem::FolderNotAFolder(folder.to_owned())
        } else {
            OutputProblem::FolderMissing(folder.to_owned())
        });
    }
    // A name too long, or anything else that keeps the path from being
    // looked at.
    if let Err(e) = looked
        && e.kind() != std::io::ErrorKind::NotFound
    {
        return fail(OutputProblem::Unusable(e));
    }
    if let Err(e) = probe(path) {
        return fail(OutputProblem::FolderUnwritable(folder.to_owned(), e));
    }
    Ok(())
}

/// Makes and removes the temporary file a write of `path` would make:
/// whether it can be written (permissions, a read-only or virtual file
/// system like `/proc`, a name too long).
pub fn probe(path: &Path) -> std::io::Result<()> {
    let (tmp, file) = create_temporary(path)?;
    drop(file);
    std::fs::remove_file(tmp)
}

/// Checks that no two of a command's `outputs` (option and path) are one
/// file: the last written would silently replace the other.
/// Compared as files (see [`same_file`]); check each with
/// [`check_replaceable`] first, so the folders exist.
pub fn check_distinct(outputs: &[(&str, &Path)]) -> Result<(), OutputError> {
    for (k, (flag, path)) in outputs.iter().enumerate() {
        if let Some((other, _)) = outputs[..k].iter().find(|(_, p)| same_file(p, path)) {
            return Err(problem(flag, path, OutputProblem::SameAs(other.to_string())));
        }
    }
    Ok(())
}

/// Checks that `path` (given as `flag`) can be written and that nothing is
/// there yet (not even a dangling link); `advice` says what to do if there
/// is.
pub fn check_new(flag: &str, path: &Path, advice: &'static str) -> Result<(), OutputError> {
    if path.symlink_metadata().is_ok() {
        return Err(problem(flag, path, OutputProblem::Exists(advice)));
    }
    check_replaceable(flag, path)
}

/// Checks a folder that a series of new files goes into (a film's
/// `frame-000001.png`, …), given as `flag`: made (with its parents) where
/// it does not exist; else it must be a folder in which a file can be made
/// and hold no file of the series yet (`prefix*.extension`), since the
/// series never overwrites; `advice` says what to do where it does.
pub fn check_series_folder(
    flag: &str,
    dir: &Path,
    (prefix, extension): (&str, &str),
    advice: &'static str,
) -> Result<(), OutputError> {
    let fail = |path: &Path, p| Err(problem(flag, path, p));
    match dir.metadata() {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            if let Err(e) = std::fs::create_dir_all(dir) {
                return fail(dir, OutputProblem::Unusable(e));
            }
        }
        Err(e) => return fail(dir, OutputProblem::Unusable(e)),
        Ok(m) if !m.is_dir() => return fail(dir, OutputProblem::NotAFolder(node_kind(m.file_type()))),
        Ok(_) => {}
    }
    let entries = std::fs::read_dir(dir).map_err(|e| problem(flag, dir, OutputProblem::Unusable(e)))?;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        let ours = name.starts_with(prefix)
            && Path::new(name.as_ref())
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case(extension));
        if ours {
            return fail(&entry.path(), OutputProblem::Exists(advice));
        }
    }
    if let Err(e) = probe(&dir.join(format!("{prefix}probe.{extension}"))) {
        return fail(dir, OutputProblem::FolderUnwritable(dir.to_owned(), e));
    }
    Ok(())
}

/// Checks that `path` (given as `flag`) ends in `.extension` (any case).
pub fn check_extension(flag: &str, path: &Path, extension: &'static str) -> Result<(), OutputError> {
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case(extension)) {
        Ok(())
    } else {
        Err(problem(flag, path, OutputProblem::Extension(extension)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_problem_is_one_line_naming_the_option_and_the_path() {
        let dir = tempfile::tempdir().unwrap();
        let taken = dir.path().join("taken.csv");
        std::fs::write(&taken, "x").unwrap();
        let missing = dir.path().join("no").join("x.csv");
        assert!(check_replaceable("--dump", &taken).is_ok());
        assert!(check_new("--out", &dir.path().join("free.csv"), "never").is_ok());

        let e = check_replaceable("--dump", dir.path()).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!("--dump {}: is a directory; give a file name", dir.path().display())
        );
        let e = check_replaceable("--dump", &missing).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!(
                "--dump {}: folder {} does not exist",
                missing.display(),
                missing.parent().unwrap().display()
            )
        );
        let e = check_new("--out", &taken, "choose another --out").unwrap_err();
        assert_eq!(
            e.to_string(),
            format!("--out {} exists already; choose another --out", taken.display())
        );
        let e = check_extension("--screenshot", &taken, "png").unwrap_err();
        assert!(e.to_string().ends_with("taken.csv: must be a .png file"), "{e}");
        assert!(check_extension("--screenshot", Path::new("a.PNG"), "png").is_ok());
    }

    #[test]
    fn a_long_name_a_file_on_the_way_and_a_shared_path_are_found_before_work() {
        let dir = tempfile::tempdir().unwrap();
        let long = dir.path().join("x".repeat(249));
        assert!(
            check_replaceable("--dump", &long).is_ok(),
            "249 characters are a valid name"
        );
        let too_long = dir.path().join("x".repeat(300));
        assert!(matches!(
            check_replaceable("--dump", &too_long).unwrap_err().problem,
            OutputProblem::Unusable(_)
        ));
        let file = dir.path().join("existing.csv");
        std::fs::write(&file, "x").unwrap();
        let e = check_replaceable("--dump", &file.join("x.csv")).unwrap_err();
        assert!(e.to_string().ends_with("existing.csv is not a folder"), "{e}");
        let dot = PathBuf::from(format!("{}/.", file.display()));
        assert!(check_replaceable("--dump", &dot).is_err());
        let e = check_distinct(&[("--dump", &file), ("--timeline", &dir.path().join("./existing.csv"))]).unwrap_err();
        assert!(e.to_string().ends_with(": --dump names the same file"), "{e}");
        assert!(check_distinct(&[("--dump", &file), ("--timeline", &long)]).is_ok());
    }

    #[test]
    fn an_output_that_is_an_input_is_refused_however_it_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("scen.ron");
        std::fs::write(&input, "x").unwrap();
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        let inputs = [("the scenario", input.as_path())];
        let dotted = dir.path().join("sub/../scen.ron");
        for output in [input.clone(), dotted] {
            let e = check_not_inputs(&[("--dump", &output)], &inputs).unwrap_err();
            assert_eq!(
                e.to_string(),
                format!(
                    "--dump {}: is the scenario this command reads; an output never replaces an input, give it \
                     another name",
                    output.display()
                )
            );
        }
        let other = dir.path().join("other.ron");
        assert!(
            check_not_inputs(&[("--dump", &other)], &inputs).is_ok(),
            "not there yet"
        );
        std::fs::write(&other, "x").unwrap();
        assert!(check_not_inputs(&[("--dump", &other)], &inputs).is_ok(), "another file");
        // The same file named relative to the working folder and absolute.
        let here = std::env::current_dir().unwrap();
        let cargo = here.join("Cargo.toml");
        assert!(same_file(Path::new("Cargo.toml"), &cargo));
        assert!(same_file(
            Path::new("./no-such-file.csv"),
            &here.join("no-such-file.csv")
        ));
        assert!(!same_file(Path::new("Cargo.toml"), &here.join("no-such-file.csv")));
        // Every check at once: the input first.
        let outputs = [
            Output::replacing("--dump", &other),
            Output::new_only("--out", &input, "never"),
        ];
        let e = check_outputs(&outputs, &inputs).unwrap_err();
        assert!(
            matches!(e.problem, OutputProblem::IsInput(_)) && e.flag == "--out",
            "{e}"
        );
    }

    #[cfg(unix)]
    #[test]
    fn a_link_to_an_input_or_a_second_name_of_it_is_the_input() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("scen.ron");
        std::fs::write(&input, "x").unwrap();
        let link = dir.path().join("link.ron");
        std::os::unix::fs::symlink(&input, &link).unwrap();
        let hard = dir.path().join("hard.ron");
        std::fs::hard_link(&input, &hard).unwrap();
        for (output, read) in [(&input, &link), (&link, &input), (&hard, &input)] {
            assert!(
                check_not_inputs(&[("--dump", output)], &[("the scenario", read)]).is_err(),
                "{} as {}",
                output.display(),
                read.display()
            );
        }
    }

    #[test]
    fn a_path_ending_in_a_slash_names_a_folder_even_if_none_is_there() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("existing.csv");
        std::fs::write(&file, "x").unwrap();
        for named in [format!("{}/", file.display()), format!("{}/new/", dir.path().display())] {
            let e = check_replaceable("--dump", Path::new(&named)).unwrap_err();
            assert!(matches!(e.problem, OutputProblem::IsDirectory), "{e}");
        }
    }

    #[cfg(unix)]
    #[test]
    fn special_files_and_links_are_neither_replaced_nor_written_through() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("f.csv");
        crate::input::make_fifo(&fifo);
        let link = dir.path().join("l.csv");
        std::os::unix::fs::symlink(dir.path().join("target.csv"), &link).unwrap();
        for (path, kind) in [
            (fifo.as_path(), "a FIFO"),
            (Path::new("/dev/null"), "a character device"),
            (link.as_path(), "a symbolic link"),
        ] {
            let e = check_replaceable("--dump", path).unwrap_err();
            assert!(e.to_string().contains(&format!(": is {kind}")), "{e}");
        }
    }

    #[cfg(unix)]
    #[test]
    fn a_folder_where_no_file_can_be_made_is_found_before_any_work() {
        let e = check_replaceable("--dump", Path::new("/proc/x.csv")).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("--dump /proc/x.csv: cannot write in folder /proc: the folder exists, but "),
            "{e}"
        );
    }
}
