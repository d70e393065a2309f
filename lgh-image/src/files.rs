//! Files in and out: input files read up to a size limit ([`read_limited`]) and atomic writes
//! ([`write_atomic`]) that take turns through one process-wide lock ([`hold_writes`]), so that a
//! program stopped at any moment leaves neither a temporary file nor half a file behind.

use std::io::{BufWriter, Read, Write};
use std::path::Path;

use crate::error::ImageError;
use crate::image::{first_non_finite, Image};

/// Input files (VDB caches, PLY point sets, OBJ and MTL files) larger than this are refused, by
/// [`read_limited`]: 8 GiB, a third of a 24 GiB machine.
pub const MAX_INPUT_BYTES: u64 = 8 << 30;

/// The bytes of the file at `path`, refused with an [`ErrorKind::FileTooLarge`] error if there
/// are more than `max_bytes`. The size a regular file reports refuses it before reading; what
/// reports none (a FIFO, a device) is read through `take(max_bytes + 1)`, so never past the limit.
///
/// [`ErrorKind::FileTooLarge`]: std::io::ErrorKind::FileTooLarge
pub fn read_limited(path: &Path, max_bytes: u64) -> std::io::Result<Vec<u8>> {
    let too_large = || {
        std::io::Error::new(
            std::io::ErrorKind::FileTooLarge,
            format!("the file is larger than the limit of {max_bytes} bytes"),
        )
    };
    let file = std::fs::File::open(path)?;
    let size = file.metadata()?.len();
    if size > max_bytes {
        return Err(too_large());
    }
    let mut bytes = Vec::with_capacity(usize::try_from(size).unwrap_or(0));
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_large());
    }
    Ok(bytes)
}

/// The process-wide write lock: which thread holds it and how many times (it is re-entrant,
/// so a caller holding it for a group of files — an EXR and its PNG — can write them through
/// [`write_atomic`], which takes it again), and a condition variable for the others.
struct WriteLock {
    owner: std::sync::Mutex<(Option<std::thread::ThreadId>, usize)>,
    free: std::sync::Condvar,
}

/// Held by every [`write_atomic`] while its file is written, and by [`hold_writes`].
static WRITING: WriteLock = WriteLock {
    owner: std::sync::Mutex::new((None, 0)),
    free: std::sync::Condvar::new(),
};

/// The write lock, held until dropped (on the thread that took it: it is not `Send`).
#[must_use = "the lock is released when the guard is dropped"]
pub struct WritesHeld {
    _not_send: std::marker::PhantomData<*const ()>,
}

impl Drop for WritesHeld {
    fn drop(&mut self) {
        let mut owner = WRITING
            .owner
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        owner.1 -= 1;
        if owner.1 == 0 {
            owner.0 = None;
            WRITING.free.notify_all();
        }
    }
}

/// Waits for the files being written, if any, and keeps any other thread's write from starting
/// while the guard lives: a program that exits holding it (on SIGINT, say) leaves neither a
/// temporary file nor half a file behind. Writes from several threads take turns through it;
/// the thread holding it may write (a group of files written together, whole or not at all).
/// The one write lock of the project.
///
/// ```
/// let dir = tempfile::tempdir()?;
/// {
///     let _held = lgh_image::hold_writes();
///     // The holder writes a pair of files; exiting here would leave every file whole.
///     lgh_image::write_atomic(&dir.path().join("a.txt"), |w| w.write_all(b"one"))?;
///     lgh_image::write_atomic(&dir.path().join("b.txt"), |w| w.write_all(b"two"))?;
/// }
/// lgh_image::write_atomic(&dir.path().join("c.txt"), |w| w.write_all(b"after"))?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn hold_writes() -> WritesHeld {
    let me = std::thread::current().id();
    let mut owner = WRITING
        .owner
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    while owner.0.is_some_and(|o| o != me) {
        owner = WRITING
            .free
            .wait(owner)
            .unwrap_or_else(std::sync::PoisonError::into_inner);
    }
    owner.0 = Some(me);
    owner.1 += 1;
    WritesHeld {
        _not_send: std::marker::PhantomData,
    }
}

/// Writes `path` atomically: `write` fills a temporary file beside it, which replaces `path` only
/// if everything succeeded. On any error the temporary file is removed and `path` is untouched.
///
/// The file gets the permissions a plain [`File::create`](std::fs::File::create) would give it
/// (on Unix `0o666 & !umask`), not the temporary file's private `0o600`: frames written on a
/// render farm must be readable by the compositor's user.
///
/// Errors: [`ImageError::TempFile`] if the temporary file cannot be created,
/// [`ImageError::Write`] if `write`, the flush, the sync or the rename fails.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), ImageError> {
    let _writing = hold_writes();
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".lgh-").suffix(".tmp");
    // `open(2)` masks the mode with the umask, exactly as for a plain `File::create`.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    let tmp = builder
        .tempfile_in(dir)
        .map_err(|source| ImageError::TempFile {
            dir: dir.to_path_buf(),
            source,
        })?;
    let write_error = |source| ImageError::Write {
        path: path.to_path_buf(),
        source,
    };
    {
        let mut w = BufWriter::new(tmp.as_file());
        write(&mut w).and_then(|_| w.flush()).map_err(write_error)?;
    }
    tmp.as_file().sync_all().map_err(write_error)?;
    tmp.persist(path).map_err(|e| write_error(e.error))?;
    Ok(())
}

/// Whether `image` may be written to `path`: [`ImageError::Empty`] if it has no pixels,
/// [`ImageError::NonFinite`] naming the first NaN or infinite pixel.
pub(crate) fn check_writable(path: &Path, image: &Image) -> Result<(), ImageError> {
    if image.width == 0 || image.height == 0 {
        return Err(ImageError::Empty {
            path: path.to_path_buf(),
        });
    }
    match first_non_finite(image) {
        Some((pixel, value)) => Err(ImageError::NonFinite {
            path: path.to_path_buf(),
            pixel,
            value,
        }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::gradient;
    use crate::write_png;

    /// The lock is one for the process: another thread's write waits for the holder, which
    /// itself writes through it (re-entrant) — what keeps a frame's EXR and PNG together when
    /// a signal arrives.
    #[test]
    fn another_thread_waits_for_the_holder_of_the_write_lock() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("late.txt");
        let done = std::sync::atomic::AtomicBool::new(false);
        std::thread::scope(|scope| {
            let held = hold_writes();
            write_atomic(&dir.path().join("mine.txt"), |w| w.write_all(b"mine")).unwrap();
            let (tx, rx) = std::sync::mpsc::channel();
            let (path, done) = (&path, &done);
            scope.spawn(move || {
                tx.send(()).unwrap();
                write_atomic(path, |w| w.write_all(b"late")).unwrap();
                done.store(true, std::sync::atomic::Ordering::SeqCst);
            });
            rx.recv().unwrap();
            std::thread::sleep(std::time::Duration::from_millis(50));
            // Still held: the other thread cannot have written.
            assert!(!done.load(std::sync::atomic::Ordering::SeqCst));
            assert!(!path.exists());
            drop(held);
        });
        assert!(done.into_inner() && path.exists());
    }

    /// The written file's mode is a plain `File::create`'s in the same folder under the same
    /// umask, whatever that umask is; the CLI tests pin it under umasks 022 and 027.
    #[cfg(unix)]
    #[test]
    fn written_files_get_the_permissions_of_a_plain_create() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        let plain = dir.path().join("plain");
        std::fs::File::create(&plain).unwrap();
        let written = dir.path().join("written.png");
        write_png(&written, &gradient(), 1.0).unwrap();
        assert_eq!(mode(&written), mode(&plain));
        // Replacing a file gives it the same mode again, not the temporary file's 0600.
        write_png(&written, &gradient(), 2.0).unwrap();
        assert_eq!(mode(&written), mode(&plain));
    }

    #[test]
    fn read_limited_refuses_files_and_streams_past_the_limit() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("ten");
        std::fs::write(&p, b"0123456789").unwrap();
        assert_eq!(read_limited(&p, 10).unwrap(), b"0123456789");
        let e = read_limited(&p, 9).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::FileTooLarge);
        assert!(
            e.to_string().contains("larger than the limit of 9 bytes"),
            "{e}"
        );
        let missing = read_limited(&dir.path().join("none"), 10).unwrap_err();
        assert_eq!(missing.kind(), std::io::ErrorKind::NotFound);
        // An endless stream whose metadata says 0 bytes: refused after max + 1 bytes.
        #[cfg(unix)]
        assert_eq!(
            read_limited(Path::new("/dev/zero"), 1000)
                .unwrap_err()
                .kind(),
            std::io::ErrorKind::FileTooLarge
        );
    }
}
