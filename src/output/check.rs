//! Checks, made before any work starts, that an output path can be written:
//! its folder exists, it is not a folder, and — for outputs that are never
//! overwritten — nothing is there yet.

use std::path::{Path, PathBuf};

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
    /// It is a folder.
    #[error(": is a directory")]
    IsDirectory,
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
}

fn problem(flag: &str, path: &Path, problem: OutputProblem) -> OutputError {
    OutputError {
        flag: flag.to_owned(),
        path: path.to_owned(),
        problem,
    }
}

/// Checks that `path` (given as `flag`) can be written, replacing any file
/// there: it is not a folder and its folder exists.
pub fn check_replaceable(flag: &str, path: &Path) -> Result<(), OutputError> {
    if path.is_dir() {
        return Err(problem(flag, path, OutputProblem::IsDirectory));
    }
    let folder = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if !folder.is_dir() {
        return Err(problem(flag, path, OutputProblem::FolderMissing(folder.to_owned())));
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
            format!("--dump {}: is a directory", dir.path().display())
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
}
