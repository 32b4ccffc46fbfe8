//! The lock a run holds on an output while it writes it, `<out>.lock`: who holds it, whether
//! that process still runs, and the taking over of a lock whose process is gone.
//!
//! The lock file holds the process id of its run on its first line, then `host <name>` and
//! `pid-namespace <id>` lines (Linux: `/proc/sys/kernel/hostname` and `/proc/self/ns/pid`).
//! A lock whose host and process-id namespace are this process's, and whose process has no
//! `/proc/<pid>`, was left by a run that was killed: the next run takes it over. A lock of
//! another host or namespace, one that names no host (a lock of an earlier version), or any
//! lock where `/proc` cannot be read is refused as before, since whether its process runs
//! cannot be seen.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use super::Output;
use crate::error::CliError;

/// Where Linux shows the processes.
const PROC: &str = "/proc";

/// Who holds a lock: the process id, host name and process-id namespace written in it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LockOwner {
    /// The process id, when the lock holds one.
    pub pid: Option<u32>,
    /// The host name, when it was known to the run that wrote the lock.
    pub host: Option<String>,
    /// The process-id namespace (`pid:[4026531836]`), when it was known to that run.
    pub pid_namespace: Option<String>,
}

/// Whether the process of a lock runs.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Holder {
    /// Its process runs.
    Running,
    /// Its process is gone: a killed run left the lock.
    Gone,
    /// Whether its process runs cannot be seen, and why.
    Unseen(String),
}

impl LockOwner {
    /// This process, as seen under `proc` (`/proc` on Linux).
    fn of_process(proc: &Path) -> Self {
        let read =
            |path: &str| std::fs::read_to_string(proc.join(path)).ok().map(|s| s.trim().to_owned());
        let link = std::fs::read_link(proc.join("self/ns/pid")).ok();
        Self {
            pid: Some(std::process::id()),
            host: read("sys/kernel/hostname").filter(|h| !h.is_empty() && !h.contains('\n')),
            pid_namespace: link.map(|l| l.to_string_lossy().into_owned()),
        }
    }

    /// This process.
    pub fn this_process() -> Self {
        Self::of_process(Path::new(PROC))
    }

    /// The text of a lock file: the process id, then `host <name>` and `pid-namespace <id>`
    /// when known.
    pub fn text(&self) -> String {
        let mut text = self.pid.map_or_else(String::new, |p| format!("{p}\n"));
        if let Some(host) = &self.host {
            text.push_str(&format!("host {host}\n"));
        }
        if let Some(ns) = &self.pid_namespace {
            text.push_str(&format!("pid-namespace {ns}\n"));
        }
        text
    }

    /// The owner a lock file's text names (a lock of an earlier version holds the process id
    /// alone).
    pub fn parse(text: &str) -> Self {
        let mut lines = text.lines().map(str::trim);
        let pid = lines.next().and_then(|l| l.parse().ok());
        let (mut host, mut pid_namespace) = (None, None);
        for line in lines {
            match line.split_once(' ') {
                Some(("host", h)) => host = Some(h.to_owned()),
                Some(("pid-namespace", n)) => pid_namespace = Some(n.to_owned()),
                _ => {}
            }
        }
        Self { pid, host, pid_namespace }
    }

    /// Whether the process of this lock runs, as `me` sees it under `proc`.
    fn state(&self, me: &LockOwner, proc: &Path) -> Holder {
        let Some(pid) = self.pid else {
            return Holder::Unseen("the lock names no process".into());
        };
        if !proc.join("self").exists() {
            return Holder::Unseen(format!(
                "whether process {pid} runs cannot be seen without {}",
                proc.display()
            ));
        }
        match (&self.host, &me.host) {
            (None, _) => {
                return Holder::Unseen(format!(
                    "the lock does not say on which host process {pid} runs"
                ));
            }
            (Some(host), mine) if Some(host) != mine.as_ref() => {
                return Holder::Unseen(format!(
                    "process {pid} runs on host {host}, whose processes cannot be seen from here"
                ));
            }
            _ => {}
        }
        if self.pid_namespace != me.pid_namespace {
            return Holder::Unseen(format!(
                "process {pid} runs in another process-id namespace ({}), whose processes \
                 cannot be seen from here",
                self.pid_namespace.as_deref().unwrap_or("unknown")
            ));
        }
        if proc.join(pid.to_string()).exists() { Holder::Running } else { Holder::Gone }
    }
}

/// The lock a run holds on an output while it writes it: `<out>.lock`, created only when
/// absent and holding the run's [`LockOwner`]; removed when dropped, whether the run succeeded
/// or not.
#[derive(Debug)]
pub struct OutputLock {
    path: PathBuf,
}

/// Attempts at taking a lock that changes hands meanwhile.
const ATTEMPTS: usize = 4;

impl OutputLock {
    /// Takes the lock of `output`; a lock whose process is gone is taken over, with a note on
    /// standard error.
    ///
    /// # Errors
    /// As [`Self::acquire_noting`].
    pub fn acquire(output: &Output) -> Result<Self, CliError> {
        Self::acquire_noting(output, &mut |note| eprintln!("note: {note}"))
    }

    /// Takes the lock of `output`. A lock file whose process is gone (its host and
    /// process-id namespace this process's, and no `/proc/<pid>`) is taken over, and `note`
    /// told so.
    ///
    /// # Errors
    /// [`CliError::Locked`] when the lock file exists and its process runs or may run (another
    /// host's or namespace's, an earlier version's lock without a host, no `/proc`);
    /// [`CliError::Output`] when it cannot be created or taken over.
    pub fn acquire_noting(output: &Output, note: &mut dyn FnMut(&str)) -> Result<Self, CliError> {
        Self::acquire_in(output, note, Path::new(PROC))
    }

    /// [`Self::acquire_noting`] with the processes seen under `proc`.
    fn acquire_in(
        output: &Output,
        note: &mut dyn FnMut(&str),
        proc: &Path,
    ) -> Result<Self, CliError> {
        let path = output.lock();
        let me = LockOwner::of_process(proc);
        let refuse = |holder: &LockOwner, why: String, path: &Path| CliError::Locked {
            output: output.given().to_owned(),
            lock: path.to_owned(),
            holder: holder.pid.map_or_else(|| "unknown".to_owned(), |p| p.to_string()),
            why,
        };
        let mut last = LockOwner { pid: None, host: None, pid_namespace: None };
        for _ in 0..ATTEMPTS {
            let file = std::fs::OpenOptions::new().write(true).create_new(true).open(&path);
            let mut file = match file {
                Ok(file) => file,
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    let text = match std::fs::read_to_string(&path) {
                        Ok(text) => text,
                        // Its run has just removed it.
                        Err(e) if e.kind() == std::io::ErrorKind::NotFound => continue,
                        Err(_) => String::new(),
                    };
                    last = LockOwner::parse(&text);
                    match last.state(&me, proc) {
                        Holder::Running => {
                            let pid = last.pid.unwrap_or_default();
                            let why = format!("its process {pid} runs: another run writes it");
                            return Err(refuse(&last, why, &path));
                        }
                        Holder::Unseen(why) => {
                            let why = format!("{why}: another run may be writing it");
                            return Err(refuse(&last, why, &path));
                        }
                        Holder::Gone => {
                            if take_over(&path, &text)? {
                                note(&format!(
                                    "took over the lock {} of process {}, which no longer runs \
                                     (a run that was killed left it)",
                                    path.display(),
                                    last.pid.unwrap_or_default()
                                ));
                            }
                            continue;
                        }
                    }
                }
                Err(e) => {
                    return Err(CliError::Output {
                        path,
                        reason: format!("cannot be created: {e}"),
                    });
                }
            };
            let lock = Self { path };
            file.write_all(me.text().as_bytes()).map_err(|e| CliError::Output {
                path: lock.path.clone(),
                reason: format!("cannot be written: {e}"),
            })?;
            return Ok(lock);
        }
        let why = "the lock changed hands while it was being taken: another run is starting \
                   on it"
            .to_owned();
        Err(refuse(&last, why, &path))
    }

    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // A lock that cannot be removed is named by the next run that finds it.
        let _ = std::fs::remove_file(&self.path);
    }
}

/// Removes the lock file `path` that held `stale`, unless another run has replaced it
/// meanwhile: the file is moved aside (atomically), and put back when it is no longer the
/// stale one. Returns whether the stale lock was removed.
///
/// # Errors
/// [`CliError::Output`] when the lock cannot be moved aside.
fn take_over(path: &Path, stale: &str) -> Result<bool, CliError> {
    static TAKEN: AtomicU64 = AtomicU64::new(0);
    let n = TAKEN.fetch_add(1, Ordering::Relaxed);
    let aside = super::suffixed(path, &format!(".stale-{}-{n}", std::process::id()));
    match std::fs::rename(path, &aside) {
        Ok(()) => {}
        // Another run took it over first.
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(false),
        Err(e) => {
            return Err(CliError::Output {
                path: path.to_owned(),
                reason: format!("is left by a run that no longer runs and cannot be removed: {e}"),
            });
        }
    }
    let moved = std::fs::read_to_string(&aside).unwrap_or_default();
    if moved != stale {
        // Another run's new lock: put back, unless a third run has made one meanwhile.
        let _ = std::fs::hard_link(&aside, path);
    }
    let _ = std::fs::remove_file(&aside);
    Ok(moved == stale)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A stand-in for `/proc` holding the processes `pids`, with this process's host and
    /// namespace files, or none.
    fn proc_with(dir: &Path, pids: &[u32], host: Option<&str>) -> std::io::Result<PathBuf> {
        let proc = dir.join("proc");
        std::fs::create_dir_all(proc.join("self/ns"))?;
        std::fs::create_dir_all(proc.join("sys/kernel"))?;
        if let Some(host) = host {
            std::fs::write(proc.join("sys/kernel/hostname"), format!("{host}\n"))?;
        }
        std::os::unix::fs::symlink("pid:[7]", proc.join("self/ns/pid"))?;
        for pid in pids {
            std::fs::create_dir(proc.join(pid.to_string()))?;
        }
        Ok(proc)
    }

    #[test]
    fn an_owner_reads_back_and_an_old_lock_holds_its_process_alone() {
        let owner = LockOwner {
            pid: Some(4242),
            host: Some("box".into()),
            pid_namespace: Some("pid:[7]".into()),
        };
        assert_eq!(owner.text(), "4242\nhost box\npid-namespace pid:[7]\n");
        assert_eq!(LockOwner::parse(&owner.text()), owner);
        let old = LockOwner::parse("4242\n");
        assert_eq!((old.pid, old.host, old.pid_namespace), (Some(4242), None, None));
        assert_eq!(LockOwner::parse("").pid, None);
    }

    #[test]
    fn a_lock_is_gone_only_when_its_process_can_be_seen_not_to_run() -> std::io::Result<()> {
        let dir = tempfile::tempdir()?;
        let proc = proc_with(dir.path(), &[10], Some("box"))?;
        let me = LockOwner::of_process(&proc);
        assert_eq!(me.host.as_deref(), Some("box"));
        assert_eq!(me.pid_namespace.as_deref(), Some("pid:[7]"));
        let lock = |pid: u32| LockOwner { pid: Some(pid), ..me.clone() };
        assert_eq!(lock(10).state(&me, &proc), Holder::Running);
        assert_eq!(lock(11).state(&me, &proc), Holder::Gone);
        // Another host, another namespace, no host, no process: unseen.
        let other_host = LockOwner { host: Some("elsewhere".into()), ..lock(11) };
        let other_ns = LockOwner { pid_namespace: Some("pid:[8]".into()), ..lock(11) };
        let no_host = LockOwner { host: None, ..lock(11) };
        let no_pid = LockOwner { pid: None, ..lock(11) };
        for (owner, why) in [
            (other_host, "on host elsewhere"),
            (other_ns, "another process-id namespace (pid:[8])"),
            (no_host, "does not say on which host"),
            (no_pid, "names no process"),
        ] {
            match owner.state(&me, &proc) {
                Holder::Unseen(text) => assert!(text.contains(why), "{text}"),
                other => panic!("{owner:?}: {other:?}"),
            }
        }
        // Without /proc nothing can be seen.
        let none = dir.path().join("none");
        match lock(11).state(&me, &none) {
            Holder::Unseen(text) => assert!(text.contains("cannot be seen without"), "{text}"),
            other => panic!("{other:?}"),
        }
        Ok(())
    }

    #[test]
    fn a_gone_holders_lock_is_taken_over_and_a_running_ones_refused() -> anyhow::Result<()> {
        let dir = tempfile::tempdir()?;
        let proc = proc_with(dir.path(), &[10], Some("box"))?;
        let out = Output::new(&dir.path().join("out.csv"))?;
        let me = LockOwner::of_process(&proc);
        let stale = LockOwner { pid: Some(11), ..me.clone() };
        std::fs::write(out.lock(), stale.text())?;
        let mut notes = Vec::new();
        let lock = OutputLock::acquire_in(&out, &mut |n| notes.push(n.to_owned()), &proc)?;
        assert_eq!(notes.len(), 1);
        assert!(notes[0].contains("took over the lock") && notes[0].contains("process 11"));
        assert_eq!(LockOwner::parse(&std::fs::read_to_string(lock.path())?), me);
        drop(lock);
        assert!(!out.lock().exists());
        let running = LockOwner { pid: Some(10), ..me };
        std::fs::write(out.lock(), running.text())?;
        let e = OutputLock::acquire_in(&out, &mut |_| {}, &proc).expect_err("running");
        assert!(e.to_string().contains("its process 10 runs"), "{e}");
        assert_eq!(std::fs::read_to_string(out.lock())?, running.text());
        Ok(())
    }

    #[test]
    fn a_lock_that_changed_hands_is_put_back() -> std::io::Result<()> {
        let dir = tempfile::tempdir()?;
        let lock = dir.path().join("out.csv.lock");
        std::fs::write(&lock, "12\nhost box\n")?;
        // The stale text was read before another run replaced the lock with its own.
        let taken = take_over(&lock, "11\nhost box\n").map_err(std::io::Error::other)?;
        assert!(!taken);
        assert_eq!(std::fs::read_to_string(&lock)?, "12\nhost box\n");
        assert!(take_over(&lock, "12\nhost box\n").map_err(std::io::Error::other)?);
        assert!(!lock.exists());
        assert!(!take_over(&lock, "12\nhost box\n").map_err(std::io::Error::other)?);
        let names: Vec<_> = std::fs::read_dir(dir.path())?.collect();
        assert!(names.is_empty(), "{names:?}");
        Ok(())
    }
}
