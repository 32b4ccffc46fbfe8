//! The files a run writes: where they go (through a symbolic link to its target), which files
//! they must not be, the lock that keeps two runs off one output, and CSV records.
//!
//! An output `OUT` is written as `OUT.partial` and renamed to `OUT` when the run has
//! succeeded; a file written in one go (a sweep's sorted rows, a merge) is written whole as
//! `OUT.tmp` and renamed over `OUT` ([`replace_file`]), so that a run killed or stopped by a
//! full disk while writing leaves the former `OUT` as it was. Data reach the disk (`fsync`)
//! before the rename. When `OUT` is a symbolic link, the files go next to the file it points
//! to, which receives the data while the link stays a link. An existing `OUT` that is not a
//! regular file (a folder, a FIFO, a device, a socket) is refused, and so is an output that is the same file
//! as an input of the run or as another of its outputs, comparing files, not path texts. While
//! a run writes `OUT`, it holds `OUT.lock` (created only when absent, holding the run's process
//! id and host, removed when the run ends); a run that finds the lock refuses to start
//! ([`CliError::Locked`]), unless the lock's process is gone ([`OutputLock`]).

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use crate::error::CliError;

mod lock;
pub use lock::{LockOwner, OutputLock};

/// The longest chain of symbolic links followed to an output's file.
const MAX_LINKS: usize = 40;

/// `path` with `suffix` appended to its file name (`out.csv` → `out.csv.partial`).
pub fn suffixed(path: &Path, suffix: &str) -> PathBuf {
    let mut s = path.as_os_str().to_owned();
    s.push(suffix);
    PathBuf::from(s)
}

/// The file a run writes to until it succeeds: `<out>.partial`.
pub fn partial_path(out: &Path) -> PathBuf {
    suffixed(out, ".partial")
}

/// The file a file is written to in full before it is renamed over it: `<path>.tmp`.
pub fn temporary_path(path: &Path) -> PathBuf {
    suffixed(path, ".tmp")
}

/// The lock file of an output: `<out>.lock`.
pub fn lock_path(out: &Path) -> PathBuf {
    suffixed(out, ".lock")
}

/// One CSV record, quoted as the `csv` crate quotes (a field that holds a comma, a double
/// quote or a line end is put in double quotes, its double quotes doubled), without its line
/// end.
///
/// # Errors
/// None in practice: the record is written to memory.
pub fn csv_record<I, S>(fields: I) -> csv::Result<String>
where
    I: IntoIterator<Item = S>,
    S: AsRef<[u8]>,
{
    let mut w =
        csv::WriterBuilder::new().terminator(csv::Terminator::Any(b'\n')).from_writer(Vec::new());
    w.write_record(fields)?;
    let mut bytes = w.into_inner().map_err(|e| csv::Error::from(e.into_error()))?;
    if bytes.last() == Some(&b'\n') {
        bytes.pop();
    }
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// The file `path` names, its symbolic links followed (the file need not exist).
fn follow_links(path: &Path) -> Result<PathBuf, CliError> {
    let mut p = path.to_owned();
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let link = std::fs::read_link(&p).map_err(|e| CliError::Output {
                    path: path.to_owned(),
                    reason: format!("is a symbolic link that cannot be read: {e}"),
                })?;
                p = match p.parent() {
                    Some(dir) if link.is_relative() => dir.join(link),
                    _ => link,
                };
            }
            _ => return Ok(p),
        }
    }
    Err(CliError::Output {
        path: path.to_owned(),
        reason: format!("is a chain of more than {MAX_LINKS} symbolic links"),
    })
}

/// The file `path` names as an absolute path without `.`, `..` or symbolic links: the path
/// itself canonicalized when it exists, else its folder canonicalized and its name joined;
/// `None` when its folder cannot be found.
fn identity(path: &Path) -> Option<PathBuf> {
    if let Ok(found) = std::fs::canonicalize(path) {
        return Some(found);
    }
    let name = path.file_name()?;
    let dir = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    Some(std::fs::canonicalize(dir).ok()?.join(name))
}

/// What kind of file, other than a regular file, `kind` is.
fn kind_of(kind: std::fs::FileType) -> &'static str {
    if kind.is_dir() {
        return "a folder";
    }
    if kind.is_symlink() {
        return "a symbolic link";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a FIFO";
        }
        if kind.is_socket() {
            return "a socket";
        }
        if kind.is_block_device() || kind.is_char_device() {
            return "a device";
        }
    }
    "not a regular file"
}

/// An output file of a run, checked before anything is written.
#[derive(Clone, Debug)]
pub struct Output {
    /// The path as given.
    given: PathBuf,
    /// The file that receives the data: the given path, or the file its symbolic link points
    /// to.
    target: PathBuf,
    /// The target as an absolute path without `.`, `..` or symbolic links.
    identity: PathBuf,
}

impl Output {
    /// The output `path`, its symbolic links followed.
    ///
    /// # Errors
    /// [`CliError::Output`] when it (or the file it points to) exists and is not a regular
    /// file, when `<path>.partial`, `<path>.tmp` or `<path>.partial.tmp` exists and is not a
    /// regular file, or when its folder cannot be found.
    pub fn new(path: &Path) -> Result<Self, CliError> {
        let refuse = |reason: String| CliError::Output { path: path.to_owned(), reason };
        let target = follow_links(path)?;
        if let Ok(m) = std::fs::metadata(&target)
            && !m.is_file()
        {
            let shown = if target == path {
                String::new()
            } else {
                format!(" (the file {} it points to)", target.display())
            };
            return Err(refuse(format!(
                "is {}{shown}, not a regular file, and is not replaced; give the path of a \
                 regular file",
                kind_of(m.file_type())
            )));
        }
        for file in written_beside(&target).into_iter().skip(1) {
            if let Ok(m) = std::fs::symlink_metadata(&file)
                && !m.is_file()
            {
                return Err(refuse(format!(
                    "its unfinished file {} is {}, not a regular file; remove it or give \
                     another output",
                    file.display(),
                    kind_of(m.file_type())
                )));
            }
        }
        let identity = identity(&target).ok_or_else(|| {
            refuse(format!(
                "its folder {} cannot be found",
                target.parent().unwrap_or(Path::new(".")).display()
            ))
        })?;
        Ok(Self { given: path.to_owned(), target, identity })
    }

    /// The path as given.
    pub fn given(&self) -> &Path {
        &self.given
    }

    /// The file that receives the data: the given path, or the file its symbolic link points
    /// to.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// `<target>.partial`, where the run writes until it succeeds.
    pub fn partial(&self) -> PathBuf {
        partial_path(&self.target)
    }

    /// `<target>.lock`, which the run holds while it writes.
    pub fn lock(&self) -> PathBuf {
        lock_path(&self.target)
    }

    /// Creates `<target>.partial` for writing.
    ///
    /// # Errors
    /// [`CliError::Output`] naming it when it cannot be created.
    pub fn create_partial(&self) -> Result<(PathBuf, BufWriter<File>), CliError> {
        let partial = self.partial();
        let file = File::create(&partial).map_err(|e| CliError::Output {
            path: partial.clone(),
            reason: format!("cannot be created: {e}"),
        })?;
        Ok((partial, BufWriter::new(file)))
    }

    /// Renames the finished `partial` file to the target.
    ///
    /// # Errors
    /// [`CliError::Output`] when the rename fails.
    pub fn publish(&self, partial: &Path) -> Result<(), CliError> {
        std::fs::rename(partial, &self.target).map_err(|e| CliError::Output {
            path: self.given.clone(),
            reason: format!("cannot be written: {e}"),
        })
    }

    /// Flushes the writer of the finished `partial` file, brings its data to the disk and
    /// renames it to the target ([`Self::publish`]): an error of the last writes (a full disk)
    /// is seen before the target is replaced.
    ///
    /// # Errors
    /// [`CliError::Output`] naming `partial` when it cannot be written to the end, or the
    /// output when the rename fails.
    pub fn publish_written(&self, partial: &Path, w: BufWriter<File>) -> Result<(), CliError> {
        finish(w, partial)?;
        self.publish(partial)
    }
}

/// The files written beside an output's `target`: the target, `<target>.partial`,
/// `<target>.tmp` and `<target>.partial.tmp`.
fn written_beside(target: &Path) -> [PathBuf; 4] {
    let partial = partial_path(target);
    [target.to_owned(), partial.clone(), temporary_path(target), temporary_path(&partial)]
}

/// Flushes `w`, the writer of `path`, and brings the file's data to the disk.
fn finish(w: BufWriter<File>, path: &Path) -> Result<(), CliError> {
    let failed = |e: std::io::Error| CliError::Output {
        path: path.to_owned(),
        reason: format!("cannot be written: {e}"),
    };
    let file = w.into_inner().map_err(|e| failed(e.into_error()))?;
    file.sync_all().map_err(failed)
}

/// Writes the file `path` whole or not at all: `write` writes `<path>.tmp` (one that a killed
/// run left is removed first), whose data are brought to the disk and which is then renamed
/// over `path`. Whatever stops the write (an error, a full disk, a killed process), `path`
/// keeps its former content. `path` is the file itself, not a symbolic link to it (see
/// [`Output::target`]).
///
/// # Errors
/// [`CliError::Output`] naming `path` when `<path>.tmp` cannot be created or written, or
/// cannot be renamed; `<path>.tmp` is removed then, and `path` is as it was.
pub fn replace_file(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> anyhow::Result<()>,
) -> Result<(), CliError> {
    let tmp = temporary_path(path);
    remove_stale(&tmp)?;
    let file =
        std::fs::OpenOptions::new().write(true).create_new(true).open(&tmp).map_err(|e| {
            CliError::Output { path: tmp.clone(), reason: format!("cannot be created: {e}") }
        })?;
    let mut w = BufWriter::new(file);
    let written = write(&mut w)
        .map_err(|e| CliError::Output {
            path: tmp.clone(),
            reason: format!("cannot be written: {e:#}"),
        })
        .and_then(|()| finish(w, &tmp))
        .and_then(|()| {
            std::fs::rename(&tmp, path).map_err(|e| CliError::Output {
                path: path.to_owned(),
                reason: format!("cannot be replaced by {}: {e}", tmp.display()),
            })
        });
    if let Err(CliError::Output { path: failed, reason }) = written {
        // The unfinished file is of no use; the file it was to replace is untouched.
        let _ = std::fs::remove_file(&tmp);
        return Err(CliError::Output {
            path: failed,
            reason: format!("{reason}; {} is left as it was", path.display()),
        });
    }
    written
}

/// Refuses outputs that are the same file as one of the `inputs` or as each other, their
/// unfinished files `<out>.partial`, `<out>.tmp` and `<out>.partial.tmp` included (a scene
/// read and then overwritten, two outputs written into one file), comparing files: absolute
/// paths without `.`, `..` or symbolic links. An input that cannot be found is left to its reader.
///
/// # Errors
/// [`CliError::Output`] naming the output and the file it would overwrite.
pub fn check_distinct(inputs: &[&Path], outputs: &[&Output]) -> Result<(), CliError> {
    let written = |o: &Output| written_beside(&o.identity);
    for (j, out) in outputs.iter().enumerate() {
        let refuse = |reason: String| CliError::Output { path: out.given.clone(), reason };
        let files = written(out);
        for input in inputs {
            let Some(read) = identity(input) else { continue };
            if read == files[0] {
                return Err(refuse(format!(
                    "is the input {} of the run, which writing it would destroy; give the \
                     output another name",
                    input.display()
                )));
            }
            if let Some(first) = files[1..].iter().find(|f| **f == read) {
                return Err(refuse(format!(
                    "would be written first to {}, which is the input {} of the run; give the \
                     output another name",
                    first.display(),
                    input.display()
                )));
            }
        }
        for earlier in &outputs[..j] {
            if written(earlier).iter().any(|f| files.contains(f)) {
                return Err(refuse(format!(
                    "is the same file as the output {} of the run (or one of its unfinished \
                     files); give each output a file of its own",
                    earlier.given.display()
                )));
            }
        }
    }
    Ok(())
}

/// Removes `path`, a file left by an earlier run of the same output that does not describe
/// this run; a file that is not there is fine.
///
/// # Errors
/// [`CliError::Output`] when it exists and cannot be removed.
pub fn remove_stale(path: &Path) -> Result<(), CliError> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(CliError::Output {
            path: path.to_owned(),
            reason: format!("is left from an earlier run and cannot be removed: {e}"),
        }),
        _ => Ok(()),
    }
}

/// Removes the files `<out>.member-<i>.failed.dat` of the target of `out` that an earlier
/// sweep wrote ([`remove_stale`]).
///
/// # Errors
/// [`CliError::Output`] when one cannot be removed, or the folder cannot be listed.
pub fn remove_stale_member_problems(out: &Output) -> Result<(), CliError> {
    let Some(name) = out.target.file_name().and_then(|n| n.to_str()) else { return Ok(()) };
    let dir = match out.target.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    let listed = |e: std::io::Error| CliError::Output {
        path: dir.to_owned(),
        reason: format!("cannot be listed for the files of an earlier sweep: {e}"),
    };
    let prefix = format!("{name}.member-");
    for entry in std::fs::read_dir(dir).map_err(listed)? {
        let entry = entry.map_err(listed)?;
        let file = entry.file_name();
        let Some(member) = file
            .to_str()
            .and_then(|f| f.strip_prefix(&prefix))
            .and_then(|f| f.strip_suffix(".failed.dat"))
        else {
            continue;
        };
        if !member.is_empty() && member.bytes().all(|b| b.is_ascii_digit()) {
            remove_stale(&dir.join(&file))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_record_is_quoted_as_the_csv_crate_quotes() -> csv::Result<()> {
        assert_eq!(csv_record(["t", "flo,or.x", "b\"x.y"])?, "t,\"flo,or.x\",\"b\"\"x.y\"");
        assert_eq!(csv_record(["plain"])?, "plain");
        Ok(())
    }
}
