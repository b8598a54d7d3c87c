//! Output files that are never half-written, committed together.
//!
//! Every output is first written in full to a temporary file ([`Staged`]); only when a whole
//! run succeeded are all of its outputs moved into place by [`commit_all`], which replaces all
//! of them or none (an existing file is set aside and put back if a later one fails).
//!
//! What "moving into place" means depends on what the output path names:
//! - a regular file, or nothing yet: the temporary file lies beside it (same folder, same file
//!   system) and is renamed onto it, atomically;
//! - a symbolic link: it is followed, and its final target is replaced (the link stays);
//! - a device (`/dev/null`, `/dev/full`), a FIFO or `/dev/fd/N` that is not a regular file: the
//!   temporary file lies in the system's temporary folder and its bytes are written through to
//!   the path when committing (the path itself is never replaced; a full device is an error);
//! - `-`: standard output, written at the end.
//!
//! Every temporary file that exists is on a list ([`exit_removing_temporaries`]), so a run
//! stopped at once (a second Ctrl-C) removes them before it exits; a commit in progress
//! finishes first.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard};

/// The temporary files of [`Staged`] outputs that exist now (created or about to be, not yet
/// moved into place or removed). [`commit_all`] holds the lock while it moves files.
static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The output folders this run created (deepest first), removed when empty by a run stopped
/// at once, as a failed run removes them ([`crate::options::remove_empty`]).
static CREATED_FOLDERS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Notes the output folders this run created (deepest first), for
/// [`exit_removing_temporaries`].
pub fn created_folders(folders: &[PathBuf]) {
    let mut list = CREATED_FOLDERS.lock().unwrap_or_else(|e| e.into_inner());
    list.clear();
    list.extend_from_slice(folders);
}

/// The list of temporary files, also after a thread panicked holding it.
fn temporaries() -> MutexGuard<'static, Vec<PathBuf>> {
    TEMPORARIES.lock().unwrap_or_else(|e| e.into_inner())
}

/// Takes `temp` off the list (it was moved into place or removed).
fn forget(list: &mut Vec<PathBuf>, temp: &Path) {
    if let Some(i) = list.iter().position(|t| t == temp) {
        list.swap_remove(i);
    }
}

/// Removes the temporary files on `list` (emptying it), then the output folders the run
/// created, where they are left empty.
fn remove_all(list: &mut Vec<PathBuf>) {
    for temp in list.drain(..) {
        let _ = std::fs::remove_file(&temp);
    }
    if let Ok(folders) = CREATED_FOLDERS.try_lock() {
        crate::options::remove_empty(&folders);
    }
}

/// How long a run stopping at once waits for a commit in progress ([`exit_removing_temporaries`]).
const COMMIT_WAIT: std::time::Duration = std::time::Duration::from_secs(1);

/// Exits the process with `code` at once, first removing every temporary file (and the output
/// folders the run created, left empty: [`created_folders`]). The list stays
/// locked until the exit, so no output is created or committed after the removal (a commit
/// in progress finishes first, for at most [`COMMIT_WAIT`]: one writing into a FIFO nobody
/// reads may block for ever, and the exit then goes ahead without the removal). `say` is
/// called just before the exit with whether the files were removed.
pub fn exit_removing_temporaries(code: i32, say: impl FnOnce(bool)) -> ! {
    let start = std::time::Instant::now();
    // Held, not dropped, until the exit.
    let mut list = loop {
        match TEMPORARIES.try_lock() {
            Ok(list) => break Some(list),
            Err(std::sync::TryLockError::Poisoned(e)) => break Some(e.into_inner()),
            Err(std::sync::TryLockError::WouldBlock) if start.elapsed() < COMMIT_WAIT => {
                std::thread::sleep(std::time::Duration::from_millis(5));
            }
            Err(std::sync::TryLockError::WouldBlock) => break None,
        }
    };
    if let Some(list) = list.as_mut() {
        remove_all(list);
    }
    say(list.is_some());
    std::process::exit(code)
}

/// How a staged file reaches its target.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    /// Renamed onto a regular file (or a new name).
    Replace,
    /// Copied into a device, FIFO or other special file.
    WriteThrough,
}

/// A finished temporary file waiting to be moved onto its target by [`commit_all`]. Dropped
/// uncommitted, it removes its temporary file.
#[derive(Debug)]
pub struct Staged {
    temp: PathBuf,
    target: PathBuf,
    mode: Mode,
    done: bool,
}

impl Staged {
    /// Plans the output `path` (not `-`): follows symbolic links and picks the temporary file.
    pub fn new(path: &Path) -> std::io::Result<Self> {
        let special = std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir());
        if special {
            let target = path.to_owned();
            let temp = std::env::temp_dir().join(temp_name(&target));
            temporaries().push(temp.clone());
            return Ok(Self {
                temp,
                target,
                mode: Mode::WriteThrough,
                done: false,
            });
        }
        let target = follow_links(path)?;
        let temp = temp_path(&target);
        temporaries().push(temp.clone());
        Ok(Self {
            temp,
            target,
            mode: Mode::Replace,
            done: false,
        })
    }

    /// The temporary file to write.
    pub fn temp(&self) -> &Path {
        &self.temp
    }

    /// The file that will be replaced (a link's target) or written through.
    pub fn target(&self) -> &Path {
        &self.target
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        let mut list = temporaries();
        if !self.done {
            let _ = std::fs::remove_file(&self.temp);
        }
        forget(&mut list, &self.temp);
    }
}

/// The final target of `path` after following symbolic links (also a dangling one: the file is
/// then created where the link points).
fn follow_links(path: &Path) -> std::io::Result<PathBuf> {
    let mut p = path.to_owned();
    for _ in 0..40 {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let link = std::fs::read_link(&p)?;
                p = match p.parent() {
                    Some(dir) => dir.join(link),
                    None => link,
                };
            }
            _ => return Ok(p),
        }
    }
    Err(std::io::Error::other(
        "too many levels of symbolic links; give the real file's path",
    ))
}

/// Moves every staged file onto its target, all or none: renames first (an existing target is
/// set aside under a temporary name), then the write-through targets; if any step fails, the
/// renamed targets get their old files back and every temporary file is removed. Returns the
/// failing target with its error.
pub fn commit_all(mut staged: Vec<Staged>) -> Result<(), (PathBuf, std::io::Error)> {
    // A run stopped at once waits for the commit ([`exit_removing_temporaries`]): it never sees a
    // target set aside. (Declared first, the guard is dropped before `staged` is.)
    let mut list = temporaries();
    // (index, set-aside old file if any) of the renames done so far.
    let mut renamed: Vec<(usize, Option<PathBuf>)> = Vec::new();
    let mut failure = None;
    let order: Vec<usize> = (0..staged.len())
        .filter(|&i| staged[i].mode == Mode::Replace)
        .chain((0..staged.len()).filter(|&i| staged[i].mode == Mode::WriteThrough))
        .collect();
    for i in order {
        let s = &staged[i];
        let result = match s.mode {
            Mode::Replace => {
                let backup = s.temp.with_extension("old");
                let had_old = std::fs::symlink_metadata(&s.target).is_ok_and(|m| m.is_file());
                let set_aside = if had_old {
                    std::fs::rename(&s.target, &backup).map(|()| Some(backup))
                } else {
                    Ok(None)
                };
                match set_aside {
                    Ok(old) => match std::fs::rename(&s.temp, &s.target) {
                        Ok(()) => {
                            renamed.push((i, old));
                            Ok(())
                        }
                        Err(e) => {
                            if let Some(old) = old {
                                let _ = std::fs::rename(old, &s.target);
                            }
                            Err(e)
                        }
                    },
                    Err(e) => Err(e),
                }
            }
            Mode::WriteThrough => write_through(&s.temp, &s.target),
        };
        if let Err(e) = result {
            failure = Some((s.target.clone(), e));
            break;
        }
    }
    match failure {
        None => {
            for (i, old) in renamed {
                staged[i].done = true;
                forget(&mut list, &staged[i].temp);
                if let Some(old) = old {
                    let _ = std::fs::remove_file(old);
                }
            }
            // Write-through temporaries are no longer needed: Drop removes them.
            Ok(())
        }
        Some(err) => {
            for (i, old) in renamed.into_iter().rev() {
                let s = &mut staged[i];
                match old {
                    Some(old) => {
                        let _ = std::fs::rename(old, &s.target);
                    }
                    None => {
                        let _ = std::fs::remove_file(&s.target);
                    }
                }
                s.done = true;
            }
            Err(err)
        }
    }
}

/// Copies `temp` into the special file `target` (opened for writing, never created or
/// replaced).
fn write_through(temp: &Path, target: &Path) -> std::io::Result<()> {
    let mut from = File::open(temp)?;
    let mut to = std::fs::OpenOptions::new().write(true).open(target)?;
    std::io::copy(&mut from, &mut to)?;
    to.flush()
}

/// A destination being written: a [`Staged`] file, or standard output.
pub struct Output {
    inner: Option<Inner>,
}

enum Inner {
    Stdout(BufWriter<std::io::Stdout>),
    File {
        writer: BufWriter<File>,
        staged: Staged,
    },
}

impl Output {
    /// Opens `path` (`-` for standard output). A file is written to a temporary file first.
    pub fn create(path: &Path) -> std::io::Result<Self> {
        if path.as_os_str() == "-" {
            return Ok(Self {
                inner: Some(Inner::Stdout(BufWriter::new(std::io::stdout()))),
            });
        }
        let staged = Staged::new(path)?;
        let file = File::create(staged.temp())?;
        Ok(Self {
            inner: Some(Inner::File {
                writer: BufWriter::new(file),
                staged,
            }),
        })
    }

    /// The writer.
    pub fn writer(&mut self) -> &mut dyn Write {
        match self.inner.as_mut() {
            Some(Inner::Stdout(w)) => w,
            Some(Inner::File { writer, .. }) => writer,
            None => unreachable!("an Output is only emptied by finish, which consumes it"),
        }
    }

    /// Flushes: standard output is done; a file is synced and returned staged for
    /// [`commit_all`].
    pub fn finish(mut self) -> std::io::Result<Option<Staged>> {
        match self.inner.take() {
            Some(Inner::Stdout(mut w)) => w.flush().map(|()| None),
            Some(Inner::File { mut writer, staged }) => {
                writer.flush()?;
                writer.get_ref().sync_all()?;
                Ok(Some(staged))
            }
            None => Ok(None),
        }
    }

    /// Finishes and moves this single output into place.
    pub fn commit(self) -> std::io::Result<()> {
        match self.finish()? {
            Some(s) => commit_all(vec![s]).map_err(|(_, e)| e),
            None => Ok(()),
        }
    }
}

/// Writes through [`Output::writer`], so an output can be owned by a writer of frames
/// ([`pneuma_core::encode::sink::TextSink`]).
impl Write for Output {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.writer().write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.writer().flush()
    }
}

/// Seeks in a file output (a MIDI file's header is written last, over the first one);
/// standard output cannot seek.
impl std::io::Seek for Output {
    fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
        match self.inner.as_mut() {
            Some(Inner::File { writer, .. }) => writer.seek(pos),
            _ => Err(std::io::Error::new(
                std::io::ErrorKind::Unsupported,
                "standard output cannot seek",
            )),
        }
    }
}

/// A unique temporary file name for `target`: `.<name>.<pid>.<n>.partial.<extension>`.
fn temp_name(target: &Path) -> String {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".into());
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    // The target's extension last, for writers that choose the format by it (the plot's PNG).
    let ext = target
        .extension()
        .map(|e| format!(".{}", e.to_string_lossy()))
        .unwrap_or_default();
    format!(".{name}.{}.{n}.partial{ext}", std::process::id())
}

/// The temporary name beside `target` that a file is written under before it is renamed
/// into place: `.<name>.<pid>.<n>.partial.<extension>` in the same folder (so the rename stays on one file
/// system).
pub fn temp_path(target: &Path) -> PathBuf {
    let dir = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_owned(),
        _ => PathBuf::from("."),
    };
    dir.join(temp_name(target))
}

/// Whether `e` is a broken pipe (the reader of standard output went away, as `| head` does):
/// the command then ends quietly, as Unix tools do.
pub fn is_broken_pipe(e: &std::io::Error) -> bool {
    e.kind() == std::io::ErrorKind::BrokenPipe
}

/// The advice to add to a failed write of `e`: " (check that the folder exists and is
/// writable)" when the folder is missing or not writable, nothing for other errors (a full
/// disk, a broken pipe, an existing file).
pub fn write_hint(e: &std::io::Error) -> &'static str {
    match e.kind() {
        std::io::ErrorKind::NotFound | std::io::ErrorKind::PermissionDenied => {
            " (check that the folder exists and is writable)"
        }
        std::io::ErrorKind::StorageFull => " (the disk or device is full)",
        _ => "",
    }
}
