//! Writing an output file without tearing it and without replacing what is not a file.
//!
//! [`write_file_atomic`] decides by what the path names, as the kernel resolves it
//! (`fs::metadata` follows every link, including `/proc`'s magic ones):
//! - a character device or a FIFO (`/dev/null`, `/dev/stdout` on a pipe, a named pipe) is
//!   written through in place: such a node is never replaced by a regular file;
//! - a path whose links pass through a file-descriptor folder (`/proc/*/fd`, `/dev/fd`, so
//!   `/dev/stdout`, `/dev/fd/3`) names an already open file: it is written through too,
//!   appending (so `bake -o /dev/stdout > f` fills `f` and nothing is renamed over it);
//! - a regular file, or nothing yet, reached through ordinary symbolic links (followed link
//!   by link, at most [`MAX_LINKS`]; the links themselves stay), is replaced atomically: a
//!   temporary file in the same folder created with mode 0600, given the old file's
//!   permissions and (best effort) owner, synced, renamed over the target, the folder synced.
//!   A new file's temporary gets the usual mode (0666 less the umask), which it keeps. Killed
//!   at any moment, this leaves the old file or the new one at the path, and at worst a stray
//!   `.NAME.PID.N.tmp` beside it, which a later write of NAME removes once process PID is gone
//!   and the file is older than [`STALE_AFTER`] (a PID from another PID namespace may look
//!   dead while its writer runs);
//! - anything else (a folder, a block device, a socket) is refused.

use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

use super::error::{FormatError, FormatResult};

/// How many symbolic links are followed before giving up (Linux's own limit).
pub const MAX_LINKS: usize = 40;

/// How old a dead writer's temporary file must be before a later write removes it.
pub const STALE_AFTER: Duration = Duration::from_secs(3600);

/// Writes `bytes` to `path` as the module documentation describes.
pub fn write_file_atomic(path: &Path, bytes: &[u8]) -> FormatResult<()> {
    let (target, through_fd) = follow_links(path)?;
    // The kernel's view: it follows /proc's magic links (/dev/stdout -> /proc/self/fd/1 ->
    // "pipe:[N]"), whose text names no path.
    match fs::metadata(path) {
        Ok(meta) if is_stream(&meta.file_type()) => write_through(path, bytes, false),
        Ok(meta) if meta.is_file() && through_fd => write_through(path, bytes, true),
        Ok(meta) if meta.is_file() => {
            // The kernel's own resolution of an existing file (exact where ".." meets a
            // linked folder); the link-by-link one for a file still to be created.
            let target = fs::canonicalize(path).unwrap_or(target);
            replace(&target, bytes, Some(&meta))
        }
        Ok(meta) => Err(not_regular(path, &meta)),
        Err(e) if e.kind() == io::ErrorKind::NotFound && !through_fd => {
            replace(&target, bytes, None)
        }
        Err(e) => Err(FormatError::io("inspect", path, e)),
    }
}

/// Refuses, before any work is done for it, an output that [`write_file_atomic`] would refuse
/// for what it is or where it is: an existing folder, another file that is neither regular nor
/// a stream, or a new file in a folder that does not exist (a permission shows at the write
/// itself). Each refusal names `path` and carries the I/O kind of its cause (`IsADirectory`,
/// `NotADirectory`, `NotFound`), as the write itself would fail.
pub fn check_writable(path: &Path) -> FormatResult<()> {
    let refuse = |kind: io::ErrorKind, why: String| {
        FormatError::io("write", path, io::Error::new(kind, why))
    };
    if path.as_os_str().as_encoded_bytes().ends_with(b"/") {
        return Err(refuse(
            io::ErrorKind::IsADirectory,
            "the path names a folder (it ends in /)".into(),
        ));
    }
    match fs::metadata(path) {
        Ok(meta) if meta.is_file() || is_stream(&meta.file_type()) => Ok(()),
        Ok(meta) => Err(not_regular(path, &meta)),
        // A new file, or a link to one: the folder it will be made in must be one
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            let (target, _) = follow_links(path)?;
            let folder = match target.parent() {
                Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
                _ => PathBuf::from("."),
            };
            match fs::metadata(&folder) {
                Ok(meta) if meta.is_dir() => Ok(()),
                Ok(_) => Err(refuse(
                    io::ErrorKind::NotADirectory,
                    format!("{} is not a folder", folder.display()),
                )),
                Err(e) if e.kind() == io::ErrorKind::NotFound => Err(refuse(
                    io::ErrorKind::NotFound,
                    format!("its folder {} does not exist", folder.display()),
                )),
                Err(e) => Err(FormatError::io("write", path, e)),
            }
        }
        // A part of the path that is not a folder (`file.bssrdf/x`), a permission
        Err(e) => Err(FormatError::io("write", path, e)),
    }
}

/// The refusal of an output that is not a regular file (nor a stream): `IsADirectory` for a
/// folder.
fn not_regular(path: &Path, meta: &fs::Metadata) -> FormatError {
    let kind = if meta.is_dir() {
        io::ErrorKind::IsADirectory
    } else {
        io::ErrorKind::Other
    };
    FormatError::io(
        "write",
        path,
        io::Error::new(
            kind,
            format!("it is {}, not a regular file", describe(&meta.file_type())),
        ),
    )
}

/// Whether `path` lies in a folder of open file descriptors (`/proc/PID/fd`, `/proc/self/fd`,
/// `/proc/PID/task/TID/fd`, `/dev/fd`): its "link" is an open file, not a path.
fn in_fd_folder(path: &Path) -> bool {
    let Some(dir) = path.parent() else {
        return false;
    };
    dir == Path::new("/dev/fd")
        || (dir.starts_with("/proc") && dir.file_name().is_some_and(|n| n == "fd"))
}

/// Whether `path` leads, through its symbolic links, into a folder of open file descriptors
/// (`/dev/stdin`, `/dev/fd/3`, `/proc/self/fd/1`): a descriptor the command inherited, written
/// through rather than replaced. `false` where the links cannot be followed.
pub fn through_descriptor(path: &Path) -> bool {
    follow_links(path).is_ok_and(|(_, through)| through)
}

/// The path a chain of symbolic links ends at (which may not exist yet), and whether the
/// chain passes through a file-descriptor folder (then that path means nothing on its own).
fn follow_links(path: &Path) -> FormatResult<(PathBuf, bool)> {
    let mut current = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        if in_fd_folder(&current) {
            return Ok((current, true));
        }
        match fs::symlink_metadata(&current) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let link = fs::read_link(&current)
                    .map_err(|e| FormatError::io("read the link", &current, e))?;
                current = match current.parent() {
                    Some(dir) if link.is_relative() => dir.join(link),
                    _ => link,
                };
            }
            _ => return Ok((current, false)),
        }
    }
    Err(FormatError::io(
        "follow the links of",
        path,
        io::Error::other(format!("more than {MAX_LINKS} symbolic links")),
    ))
}

#[cfg(unix)]
fn is_stream(kind: &fs::FileType) -> bool {
    use std::os::unix::fs::FileTypeExt;
    kind.is_char_device() || kind.is_fifo()
}

#[cfg(not(unix))]
fn is_stream(_kind: &fs::FileType) -> bool {
    false
}

fn describe(kind: &fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_block_device() {
            return "a block device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    if kind.is_dir() {
        "a folder"
    } else {
        "a special file"
    }
}

/// Writes into an existing device, FIFO or open file without creating or truncating anything
/// (appending to a regular file).
fn write_through(target: &Path, bytes: &[u8], append: bool) -> FormatResult<()> {
    let mut file = OpenOptions::new()
        .write(true)
        .append(append)
        .open(target)
        .map_err(|e| FormatError::io("open", target, e))?;
    file.write_all(bytes)
        .and_then(|()| file.flush())
        .map_err(|e| FormatError::io("write", target, e))
}

/// Replaces the regular file `target` (or creates it) through a synced temporary file.
fn replace(target: &Path, bytes: &[u8], old: Option<&fs::Metadata>) -> FormatResult<()> {
    let name = target
        .file_name()
        .ok_or_else(|| {
            FormatError::io(
                "write",
                target,
                io::Error::other("the path has no file name"),
            )
        })?
        .to_string_lossy()
        .into_owned();
    let dir = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    remove_stale_temps(&dir, &name);
    let (mut file, tmp) = create_temp(&dir, &name, old.is_some())?;
    let result = (|| {
        file.write_all(bytes)
            .map_err(|e| FormatError::io("write", &tmp, e))?;
        // Owner first, then the mode: a write or chown clears set-id bits.
        if let Some(meta) = old {
            take_owner(&file, meta);
            file.set_permissions(meta.permissions())
                .map_err(|e| FormatError::io("set the permissions of", &tmp, e))?;
        }
        file.sync_all()
            .map_err(|e| FormatError::io("sync", &tmp, e))?;
        drop(file);
        fs::rename(&tmp, target).map_err(|e| FormatError::io("rename over", target, e))?;
        sync_dir(&dir)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// The temporary name of attempt `attempt` of process `pid` writing `name`.
fn temp_name(name: &str, pid: u32, attempt: u32) -> String {
    format!(".{name}.{pid}.{attempt}.tmp")
}

/// Gives the temporary `file` the owner and group of the file it replaces. Best effort: only
/// root may give a file away, and a failure leaves the writer's own ids.
#[cfg(unix)]
fn take_owner(file: &File, old: &fs::Metadata) {
    use std::os::unix::fs::MetadataExt;
    let _ = std::os::unix::fs::fchown(file, Some(old.uid()), Some(old.gid()));
}

#[cfg(not(unix))]
fn take_owner(_file: &File, _old: &fs::Metadata) {}

/// Creates a fresh temporary file in `dir`; `private`: with mode 0600, so that nobody reads
/// the new content before it has the permissions of the file it replaces.
fn create_temp(dir: &Path, name: &str, private: bool) -> FormatResult<(File, PathBuf)> {
    let pid = std::process::id();
    let mut last = None;
    for attempt in 0..1000u32 {
        let tmp = dir.join(temp_name(name, pid, attempt));
        let mut options = OpenOptions::new();
        options.write(true).create_new(true);
        #[cfg(unix)]
        if private {
            use std::os::unix::fs::OpenOptionsExt;
            options.mode(0o600);
        }
        #[cfg(not(unix))]
        let _ = private;
        match options.open(&tmp) {
            Ok(file) => return Ok((file, tmp)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => last = Some(e),
            Err(e) => return Err(FormatError::io("create", &tmp, e)),
        }
    }
    let e = last.unwrap_or_else(|| io::Error::other("no free temporary name"));
    Err(FormatError::io("create a temporary file in", dir, e))
}

/// Removes the `.NAME.PID.N.tmp` files that writers of `name` killed before their rename left
/// in `dir`: only those whose process PID no longer runs and that were last written more than
/// [`STALE_AFTER`] ago. Best effort; errors are ignored.
fn remove_stale_temps(dir: &Path, name: &str) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    let prefix = format!(".{name}.");
    for entry in entries.flatten() {
        let file_name = entry.file_name();
        let Some(rest) = file_name
            .to_str()
            .and_then(|f| f.strip_prefix(&prefix))
            .and_then(|f| f.strip_suffix(".tmp"))
        else {
            continue;
        };
        let Some((pid, attempt)) = rest.split_once('.') else {
            continue;
        };
        let (Ok(pid), Ok(_)) = (pid.parse::<u32>(), attempt.parse::<u32>()) else {
            continue;
        };
        let old = entry
            .metadata()
            .and_then(|m| m.modified())
            .ok()
            .and_then(|t| SystemTime::now().duration_since(t).ok())
            .is_some_and(|age| age > STALE_AFTER);
        if old && process_is_gone(pid) {
            let _ = fs::remove_file(entry.path());
        }
    }
}

/// Whether process `pid` has certainly ended (Linux's /proc; elsewhere never assumed).
fn process_is_gone(pid: u32) -> bool {
    if pid == std::process::id() {
        return false;
    }
    let proc_root = Path::new("/proc");
    proc_root.join("self").exists() && !proc_root.join(pid.to_string()).exists()
}

#[cfg(unix)]
fn sync_dir(dir: &Path) -> FormatResult<()> {
    File::open(dir)
        .and_then(|d| d.sync_all())
        .map_err(|e| FormatError::io("sync folder", dir, e))
}

#[cfg(not(unix))]
fn sync_dir(_dir: &Path) -> FormatResult<()> {
    // Folders cannot be opened for syncing here; the rename is as durable as the OS makes it.
    Ok(())
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    #[test]
    fn a_dangling_link_creates_its_target_and_a_cycle_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::os::unix::fs::symlink("target.bin", d.join("link.bin")).unwrap();
        write_file_atomic(&d.join("link.bin"), b"abc").unwrap();
        assert_eq!(fs::read(d.join("target.bin")).unwrap(), b"abc");
        assert!(fs::symlink_metadata(d.join("link.bin"))
            .unwrap()
            .file_type()
            .is_symlink());
        std::os::unix::fs::symlink("b", d.join("a")).unwrap();
        std::os::unix::fs::symlink("a", d.join("b")).unwrap();
        let err = write_file_atomic(&d.join("a"), b"x").unwrap_err();
        assert!(
            err.to_string().contains("more than 40 symbolic links"),
            "{err}"
        );
    }

    #[test]
    fn check_writable_refuses_with_the_kind_of_the_cause_naming_the_path() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        fs::write(d.join("file"), b"").unwrap();
        let kind = |path: &Path| match check_writable(path) {
            Err(FormatError::Io {
                path: named,
                source,
                ..
            }) => {
                assert_eq!(named, path);
                source.kind()
            }
            other => panic!("{other:?}"),
        };
        assert_eq!(kind(&d.join("nosuch/x.bin")), io::ErrorKind::NotFound);
        assert_eq!(kind(&d.join("x/")), io::ErrorKind::IsADirectory);
        assert_eq!(kind(d), io::ErrorKind::IsADirectory);
        assert_eq!(kind(&d.join("file/x.bin")), io::ErrorKind::NotADirectory);
        assert!(check_writable(&d.join("file")).is_ok());
        assert!(check_writable(&d.join("new.bin")).is_ok());
    }

    #[test]
    fn descriptor_folders_are_recognised() {
        for fd in [
            "/dev/fd/1",
            "/proc/self/fd/1",
            "/proc/42/fd/3",
            "/proc/1/task/7/fd/0",
        ] {
            assert!(in_fd_folder(Path::new(fd)), "{fd}");
        }
        for plain in ["/dev/stdout", "/proc/self/status", "/tmp/fd/1", "fd/1", "/"] {
            assert!(!in_fd_folder(Path::new(plain)), "{plain}");
        }
    }

    #[test]
    fn a_link_through_a_linked_folder_replaces_the_file_the_kernel_finds() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        fs::create_dir_all(d.join("real/sub")).unwrap();
        fs::write(d.join("real/x.bin"), b"old").unwrap();
        std::os::unix::fs::symlink("real/sub", d.join("alias")).unwrap();
        // alias/link -> ../x.bin: the kernel goes to real/x.bin; joining text gives d/x.bin.
        std::os::unix::fs::symlink("../x.bin", d.join("real/sub/link")).unwrap();
        write_file_atomic(&d.join("alias/link"), b"new").unwrap();
        assert_eq!(fs::read(d.join("real/x.bin")).unwrap(), b"new");
        assert!(!d.join("x.bin").exists());
    }

    #[test]
    fn stale_temporaries_are_parsed_strictly() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        // Not of this writer's pattern: kept, whatever the PID.
        for name in [
            ".t.bin.x.0.tmp",
            ".t.bin.4194305.tmp",
            ".t.binx.4194305.0.tmp",
        ] {
            fs::write(d.join(name), b"").unwrap();
        }
        // A dead PID: removed only once the file is older than STALE_AFTER (the PID may be
        // another namespace's, whose writer still runs).
        fs::write(d.join(".t.bin.4194305.7.tmp"), b"").unwrap();
        fs::write(d.join(".t.bin.4194305.8.tmp"), b"").unwrap();
        let old = SystemTime::now() - STALE_AFTER - Duration::from_secs(60);
        File::options()
            .write(true)
            .open(d.join(".t.bin.4194305.7.tmp"))
            .unwrap()
            .set_modified(old)
            .unwrap();
        write_file_atomic(&d.join("t.bin"), b"new").unwrap();
        assert!(d.join(".t.bin.4194305.8.tmp").exists());
        assert!(d.join(".t.bin.x.0.tmp").exists());
        assert!(d.join(".t.bin.4194305.tmp").exists());
        assert!(d.join(".t.binx.4194305.0.tmp").exists());
        if Path::new("/proc/self").exists() {
            assert!(!d.join(".t.bin.4194305.7.tmp").exists());
        }
    }
}
