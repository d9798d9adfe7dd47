//! Output helpers shared by every scene: atomic file writes.
//!
//! [`write_atomic`] writes a whole file through a temporary sibling ([`TempFile`]) and a
//! rename, so a reader never sees a partial output file, even when the run is interrupted:
//! the temporary files alive at any moment are listed, and [`remove_live_temporaries`] (called
//! by the `cellsurf` program on Ctrl-C or SIGTERM) deletes them. [`check_output`] refuses,
//! before any work, an output whose folder is missing or that is not a regular file (a
//! symbolic link, a device, a FIFO or a folder would be replaced by the rename).
//!
//! A run that writes several outputs can hold them all back ([`hold_outputs`]): finished
//! temporaries are then moved into place together by [`publish_held`] once the whole run
//! succeeded, or removed by [`discard_held`] when it failed, so that a failed run leaves none
//! of its outputs (and every file it would have replaced as it was).

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

/// The temporary files being written now (and finished ones held back).
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
/// Whether finished outputs are held back until [`publish_held`].
static HOLD: AtomicBool = AtomicBool::new(false);
/// Finished outputs held back: (temporary, output).
static HELD: Mutex<Vec<(PathBuf, PathBuf)>> = Mutex::new(Vec::new());
/// Files of an earlier output that the held outputs replace, removed once they are in place
/// ([`retire`]).
static RETIRING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
/// The files [`retire`] removed, for the program to say.
static RETIRED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// From now on, finished outputs ([`TempFile::commit`], [`publish`]) stay in their
/// temporaries until [`publish_held`] (or [`discard_held`]).
pub fn hold_outputs() {
    HOLD.store(true, Ordering::SeqCst);
}

/// Moves every held output into place, in the order they were finished, and stops holding;
/// then, where every one is in place, removes the files they retire ([`retire`]).
pub fn publish_held() -> io::Result<()> {
    HOLD.store(false, Ordering::SeqCst);
    let held = std::mem::take(&mut *HELD.lock().unwrap_or_else(|e| e.into_inner()));
    let retiring = std::mem::take(&mut *RETIRING.lock().unwrap_or_else(|e| e.into_inner()));
    let mut first_err = None;
    for (tmp, out) in held {
        let r = move_into_place(&tmp, &out);
        if r.is_err() {
            remove_path(&tmp);
        }
        forget_live(&tmp);
        if let Err(e) = r {
            first_err.get_or_insert(io::Error::new(
                e.kind(),
                format!("moving {} into place: {e}", out.display()),
            ));
        }
    }
    if first_err.is_none() {
        retire_now(&retiring)?;
    }
    first_err.map_or(Ok(()), Err)
}

/// Marks `files` (of an earlier output, which the run's outputs replace: a `.npy` set's field
/// files that the new set does not write) for removal once the run's outputs are in place:
/// at [`publish_held`] while outputs are held (a run that fails or is interrupted leaves them
/// as they were), at once otherwise. Only regular files are removed.
pub fn retire(files: &[PathBuf]) -> io::Result<()> {
    if HOLD.load(Ordering::SeqCst) {
        if let Ok(mut r) = RETIRING.lock() {
            r.extend(files.iter().cloned());
        }
        Ok(())
    } else {
        retire_now(files)
    }
}

fn retire_now(files: &[PathBuf]) -> io::Result<()> {
    for c in files {
        if fs::symlink_metadata(c).is_ok_and(|m| m.file_type().is_file()) {
            fs::remove_file(c).map_err(|e| {
                io::Error::new(
                    e.kind(),
                    format!("removing {}, left from an earlier run: {e}", c.display()),
                )
            })?;
            if let Ok(mut r) = RETIRED.lock() {
                r.push(c.clone());
            }
        }
    }
    Ok(())
}

/// The files [`retire`] has removed so far (emptied by the call).
pub fn take_retired() -> Vec<PathBuf> {
    std::mem::take(&mut *RETIRED.lock().unwrap_or_else(|e| e.into_inner()))
}

/// Removes every held output's temporary (the run failed) and stops holding; returns how many
/// outputs were dropped.
pub fn discard_held() -> usize {
    HOLD.store(false, Ordering::SeqCst);
    RETIRING.lock().unwrap_or_else(|e| e.into_inner()).clear();
    let held = std::mem::take(&mut *HELD.lock().unwrap_or_else(|e| e.into_inner()));
    for (tmp, _) in &held {
        remove_path(tmp);
        forget_live(tmp);
    }
    held.len()
}

/// The length in bytes of the finished output `output`: of its held temporary while outputs
/// are held, else of the file itself.
pub fn output_len(output: &Path) -> io::Result<u64> {
    let held = HELD.lock().ok().and_then(|h| {
        h.iter()
            .rev()
            .find(|(_, o)| o == output)
            .map(|(t, _)| t.clone())
    });
    fs::metadata(held.as_deref().unwrap_or(output)).map(|m| m.len())
}

/// Moves the finished temporary `tmp` (a file or a folder) onto `output`: at once, or, while
/// outputs are held ([`hold_outputs`]), at [`publish_held`].
pub fn publish(tmp: &Path, output: &Path) -> io::Result<()> {
    if HOLD.load(Ordering::SeqCst) {
        if let Ok(mut live) = LIVE.lock()
            && !live.iter().any(|p| p == tmp)
        {
            live.push(tmp.to_path_buf());
        }
        if let Ok(mut held) = HELD.lock() {
            held.push((tmp.to_path_buf(), output.to_path_buf()));
        }
        Ok(())
    } else {
        move_into_place(tmp, output)
    }
}

/// Renames `tmp` onto `output`; an existing folder at `output` (a Zarr store written before)
/// is moved aside first and removed after.
fn move_into_place(tmp: &Path, output: &Path) -> io::Result<()> {
    let is_dir = fs::symlink_metadata(output).is_ok_and(|m| m.is_dir());
    if !is_dir {
        return fs::rename(tmp, output);
    }
    let old = temp_path(output).with_extension("old");
    let _ = fs::remove_dir_all(&old);
    fs::rename(output, &old)?;
    fs::rename(tmp, output)?;
    let _ = fs::remove_dir_all(&old);
    Ok(())
}

fn remove_path(p: &Path) {
    if p.is_dir() {
        let _ = fs::remove_dir_all(p);
    } else {
        let _ = fs::remove_file(p);
    }
}

fn forget_live(p: &Path) {
    if let Ok(mut live) = LIVE.lock() {
        live.retain(|q| q != p);
    }
}

/// A temporary sibling of an output file while it is written ([`temp_path`]). It is listed
/// for [`remove_live_temporaries`] while alive, and removed when dropped unless
/// [`TempFile::commit`] renamed it onto its output (or held it back for [`publish_held`]).
#[derive(Debug)]
pub struct TempFile {
    /// Empty once handed over to the held outputs.
    path: PathBuf,
}

impl TempFile {
    /// The temporary sibling of `output` (not created yet).
    pub fn new(output: &Path) -> TempFile {
        let path = temp_path(output);
        if let Ok(mut live) = LIVE.lock() {
            live.push(path.clone());
        }
        TempFile { path }
    }

    /// Its path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Moves the finished file onto `output` ([`publish`]: at once, or with the other held
    /// outputs once the run succeeded).
    pub fn commit(mut self, output: &Path) -> io::Result<()> {
        if HOLD.load(Ordering::SeqCst) {
            let path = std::mem::take(&mut self.path);
            publish(&path, output)
        } else {
            fs::rename(&self.path, output)
        }
    }

    /// Renames it onto `output` now, even while outputs are held: for the parts of an output
    /// that is itself still a temporary (the files inside a Zarr store being written).
    pub fn commit_now(self, output: &Path) -> io::Result<()> {
        fs::rename(&self.path, output)
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if self.path.as_os_str().is_empty() {
            return;
        }
        // Published while outputs are held (a store folder or a streamed file moved by
        // `publish`): it now belongs to the held outputs.
        let held = HELD
            .lock()
            .is_ok_and(|h| h.iter().any(|(t, _)| t == &self.path));
        if held {
            return;
        }
        let _ = fs::remove_file(&self.path);
        forget_live(&self.path);
    }
}

/// `text` cut to its first 200 characters (library errors can carry whole byte dumps).
pub fn short(text: &str) -> String {
    match text.char_indices().nth(200) {
        Some((i, _)) => format!("{} ...", &text[..i]),
        None => text.to_string(),
    }
}

/// A NetCDF-3 writer's error as a message: an I/O error's own text (the writer keeps only its
/// kind: "no storage space"), else the writer's description, shortened.
pub fn netcdf_write_reason(e: &netcdf3::WriteError) -> String {
    match e {
        netcdf3::WriteError::IOErrorKind(k) => io::Error::from(*k).to_string(),
        other => short(&format!("NetCDF-3 writer: {other:?}")),
    }
}

/// Set once the run is being interrupted ([`remove_live_temporaries`]).
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Whether the run is being interrupted: writers should start nothing more (a Zarr store's
/// chunk writes then fail, so that its temporary folder can be removed whole).
pub fn interrupted() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
}

/// Deletes every temporary file (or temporary store folder) being written (for an
/// interrupted run), after marking the run as interrupted ([`interrupted`]). A folder that a
/// writer still in flight refills is removed again, until it has stayed away for 30 ms (at
/// most half a second).
pub fn remove_live_temporaries() {
    INTERRUPTED.store(true, Ordering::SeqCst);
    let dirs: Vec<PathBuf> = LIVE
        .lock()
        .map(|l| l.iter().filter(|p| p.is_dir()).cloned().collect())
        .unwrap_or_default();
    remove_live_temporaries_where(|_| true);
    let mut absent = 0;
    for _ in 0..50 {
        if dirs.is_empty() || absent >= 3 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
        absent += 1;
        for d in dirs.iter().filter(|d| d.exists()) {
            absent = 0;
            let _ = fs::remove_dir_all(d);
        }
    }
}

/// Deletes the temporary files (or store folders) being written whose path satisfies `select`
/// ([`remove_live_temporaries`] for all of them).
pub fn remove_live_temporaries_where(select: impl Fn(&Path) -> bool) {
    if let Ok(live) = LIVE.lock() {
        for p in live.iter().filter(|p| select(p)) {
            if p.is_dir() {
                let _ = fs::remove_dir_all(p);
            } else {
                let _ = fs::remove_file(p);
            }
        }
    }
}

/// Checks, before a run, that `path` can be written as an output: its folder exists and takes
/// a new file (a probe file beside the output is made and removed: a read-only folder is
/// refused before the run, not after it), and the path is either absent or a regular file.
/// `option` names the command-line option in the error.
pub fn check_output(option: &str, path: &Path) -> io::Result<()> {
    let fail = |why: &str| {
        Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{option} {}: {why}", path.display()),
        ))
    };
    // (a name that ends in a separator names a folder: `x.nc/` would otherwise be written as
    // `x.nc`, or fail only at the final rename)
    if path
        .as_os_str()
        .as_encoded_bytes()
        .last()
        .is_some_and(|&b| std::path::is_separator(b as char))
    {
        return fail("ends in a path separator, which names a folder; give a file name");
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return fail("the folder does not exist");
    }
    match fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => {
            return fail("is a symbolic link; give the file it points to");
        }
        Ok(m) if !m.is_file() => {
            return fail("exists and is not a regular file (a folder, device or FIFO)");
        }
        _ => {}
    }
    let mut probe = temp_path(path).into_os_string();
    probe.push(".probe");
    match fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
    {
        Ok(f) => {
            drop(f);
            let _ = fs::remove_file(&probe);
            Ok(())
        }
        // (left by a run killed between the two calls: the folder takes files)
        Err(e) if e.kind() == io::ErrorKind::AlreadyExists => Ok(()),
        Err(e) => fail(&format!("its folder cannot be written ({e})")),
    }
}

/// The temporary sibling used while `path` is being written: `.NAME.tmp-PID` in the same
/// folder, so that the final rename stays on one file system.
pub fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".to_string());
    let tmp = format!(".{name}.tmp-{}", std::process::id());
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.join(tmp),
        _ => PathBuf::from(tmp),
    }
}

/// Writes `path` atomically: `fill` writes into a buffered temporary file, which is renamed
/// onto `path` only when `fill` succeeded. On any error the temporary file is removed and
/// `path` is left as it was.
pub fn write_atomic_with<F>(path: &Path, fill: F) -> io::Result<()>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    check_output("output", path)?;
    let tmp = TempFile::new(path);
    let file = fs::File::create(tmp.path())?;
    let mut w = io::BufWriter::new(file);
    fill(&mut w)?;
    let file = w.into_inner().map_err(|e| e.into_error())?;
    file.sync_all()?;
    tmp.commit(path)
}

/// The files of an earlier `.npy` set at `sidecar` (its JSON, `STEM.json`, as
/// [`crate::ripple::output::write_npy`] and the tile streams write it) that a new set of the
/// files `new` does not replace: those the old sidecar lists under `"file"`, beside it, that
/// are not in `new`. Files the old sidecar does not list, or with no sidecar at all, are never
/// named: only cellsurf's own outputs are retired.
pub fn stale_npy_files(sidecar: &Path, new: &[PathBuf]) -> Vec<PathBuf> {
    let Ok(text) = fs::read_to_string(sidecar) else {
        return Vec::new();
    };
    let dir = sidecar.parent().unwrap_or(Path::new(""));
    let mut out = Vec::new();
    for part in text.split("\"file\": \"").skip(1) {
        let Some((name, _)) = part.split_once('"') else {
            continue;
        };
        // (a plain file name beside the sidecar, as the writers record it)
        if name.contains(['/', '\\']) || !name.ends_with(".npy") {
            continue;
        }
        let p = dir.join(name);
        if !new.contains(&p) && !out.contains(&p) {
            out.push(p);
        }
    }
    out
}

/// Writes `bytes` to `path` atomically (see [`write_atomic_with`]).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_atomic_with(path, |w| w.write_all(bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A disk-full NetCDF write is said as the I/O error's text, as the other formats say it,
    /// not as the writer's type name.
    #[test]
    fn netcdf_write_reason_says_the_io_error() {
        for kind in [io::ErrorKind::StorageFull, io::ErrorKind::PermissionDenied] {
            let r = netcdf_write_reason(&netcdf3::WriteError::IOErrorKind(kind));
            assert_eq!(r, io::Error::from(kind).to_string());
            assert!(
                !r.contains("IOErrorKind") && !r.contains("StorageFull"),
                "{r}"
            );
        }
        assert_eq!(
            netcdf_write_reason(&netcdf3::WriteError::IOErrorKind(
                io::ErrorKind::StorageFull
            )),
            "no storage space"
        );
    }

    #[test]
    fn atomic_write_replaces_whole_file_and_leaves_no_temporary() {
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        let dir =
            std::env::temp_dir().join(format!("cellsurf-io-atomic-{}-{nanos}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.txt");
        write_atomic(&p, b"first").unwrap();
        write_atomic(&p, b"second").unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"second");
        assert!(!temp_path(&p).exists());
        let _ = fs::remove_dir_all(&dir);
    }

    #[test]
    #[cfg(unix)]
    fn symbolic_links_and_special_files_are_refused() {
        let dir = std::env::temp_dir().join(format!("cellsurf-io3-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let real = dir.join("real.txt");
        write_atomic(&real, b"kept").unwrap();
        let link = dir.join("link.txt");
        let _ = fs::remove_file(&link);
        std::os::unix::fs::symlink(&real, &link).unwrap();
        let e = write_atomic(&link, b"new").unwrap_err().to_string();
        assert!(e.contains("symbolic link"), "{e}");
        assert!(
            fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(fs::read(&real).unwrap(), b"kept");
        let e = check_output("--out", Path::new("/dev/null"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("not a regular file"), "{e}");
        let e = check_output("--out", &dir.join("missing/x.nc"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("--out ") && e.contains("folder does not exist"),
            "{e}"
        );
        assert!(check_output("--out", &dir.join("new.nc")).is_ok());
        // the probe leaves nothing behind
        let left = fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name());
        let probes: Vec<_> = left
            .filter(|n| n.to_string_lossy().ends_with(".probe"))
            .collect();
        assert!(probes.is_empty(), "{probes:?}");
        // a trailing separator names a folder, not the file before it
        let slashed = PathBuf::from(format!("{}/", dir.join("new.nc").display()));
        let e = check_output("--out", &slashed).unwrap_err().to_string();
        assert!(e.contains("ends in a path separator"), "{e}");
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn live_temporaries_are_listed_until_committed_or_dropped() {
        let dir = std::env::temp_dir().join(format!("cellsurf-io4-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let out = dir.join("c.txt");
        let t = TempFile::new(&out);
        fs::write(t.path(), b"partial").unwrap();
        assert!(LIVE.lock().unwrap().contains(&t.path().to_path_buf()));
        // only this test's own: tests run in parallel in one process, and removing another
        // test's live temporary would fail its rename
        remove_live_temporaries_where(|p| p.starts_with(&dir));
        assert!(
            !t.path().exists(),
            "an interrupted run leaves no temporary file"
        );
        drop(t);
        assert!(!LIVE.lock().unwrap().iter().any(|p| p.starts_with(&dir)));
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn failed_fill_keeps_old_file() {
        let dir = std::env::temp_dir().join(format!("cellsurf-io2-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let p = dir.join("b.txt");
        write_atomic(&p, b"old").unwrap();
        let r = write_atomic_with(&p, |w| {
            w.write_all(b"partial")?;
            Err(io::Error::other("interrupted"))
        });
        assert!(r.is_err());
        assert_eq!(fs::read(&p).unwrap(), b"old");
        assert!(!temp_path(&p).exists());
        let _ = fs::remove_dir_all(&dir);
    }
}
