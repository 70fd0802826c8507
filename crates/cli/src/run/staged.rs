//! An output written as the run goes: appended to `.NAME.partial` in the output directory and
//! renamed to `NAME` when the run completes (`crate::atomic::persist`). Its length and the hash of its bytes are kept as
//! it is written, so that a checkpoint records how far it had got, and a resume finds the same
//! bytes, cuts what came after, and appends from there: neither memory nor the checkpoint holds
//! the outputs.

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use tempfile::TempPath;

use super::checkpoint::Progress;
use super::hash::{self, Hasher};
use crate::atomic::OnFailure;

/// The partial file of the output at `path`: `.NAME.partial` beside it.
pub fn partial_path(path: &Path) -> PathBuf {
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    path.with_file_name(format!(".{name}.partial"))
}

/// A file that counts and hashes what reaches it.
struct Hashed {
    file: File,
    len: u64,
    hash: Hasher,
}

impl Write for Hashed {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.file.write(buf)?;
        self.hash.update(&buf[..n]);
        self.len += n as u64;
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

/// An output being written; dropped before [`commit`](Self::commit) or [`keep`](Self::keep),
/// its partial file is removed.
pub struct Staged {
    path: PathBuf,
    /// Declared before `partial`, so that it is closed before the partial file is removed.
    out: BufWriter<Hashed>,
    /// The partial file: removed when dropped, unless kept or renamed into place.
    partial: TempPath,
}

impl Staged {
    /// Starts the output at `path` afresh (an earlier partial file is replaced).
    pub fn create(path: PathBuf) -> Result<Self, String> {
        let partial = partial_path(&path);
        let file = File::create(&partial).map_err(|e| fail(&partial, e))?;
        Self::open(path, partial, file, 0, hash::hasher())
    }

    /// Continues the output at `path` from where a checkpoint left it: its partial file must
    /// start with the `progress.len` bytes the checkpoint hashed; anything after them (written
    /// after the checkpoint) is cut.
    pub fn reopen(path: PathBuf, progress: Progress) -> Result<Self, String> {
        let partial = partial_path(&path);
        let refuse = |why: String| {
            format!(
                "cannot resume {}: {} {why}",
                path.display(),
                partial.display()
            )
        };
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .open(&partial)
            .map_err(|e| {
                refuse(format!(
                    "cannot be opened ({e}); resume with the --out the run was started with"
                ))
            })?;
        let len = file.metadata().map_err(|e| refuse(e.to_string()))?.len();
        if len < progress.len {
            return Err(refuse(format!(
                "holds {len} bytes, fewer than the {} the checkpoint records",
                progress.len
            )));
        }
        let mut h = hash::hasher();
        let mut buf = vec![0u8; 1 << 20];
        let mut left = progress.len;
        while left > 0 {
            let n = buf.len().min(left as usize);
            file.read_exact(&mut buf[..n])
                .map_err(|e| refuse(e.to_string()))?;
            h.update(&buf[..n]);
            left -= n as u64;
        }
        if h.clone().finalize() != progress.hash {
            return Err(refuse(format!(
                "does not hold the bytes the checkpoint records (its first {} bytes differ): \
                 the checkpoint belongs to another run, or the file was changed",
                progress.len
            )));
        }
        file.set_len(progress.len)
            .and_then(|()| file.seek(SeekFrom::Start(progress.len)).map(|_| ()))
            .map_err(|e| refuse(e.to_string()))?;
        Self::open(path, partial, file, progress.len, h)
    }

    /// The output at `path` continued from `len` bytes in its partial file, open as `file`.
    fn open(
        path: PathBuf,
        partial: PathBuf,
        file: File,
        len: u64,
        hash: Hasher,
    ) -> Result<Self, String> {
        let partial = TempPath::try_from_path(partial).map_err(|e| fail(&path, e))?;
        let hashed = Hashed { file, len, hash };
        Ok(Self {
            path,
            out: BufWriter::with_capacity(1 << 20, hashed),
            partial,
        })
    }

    pub fn writer(&mut self) -> &mut impl Write {
        &mut self.out
    }

    /// Bytes written so far (buffered ones included).
    pub fn written(&self) -> u64 {
        self.out.get_ref().len + self.out.buffer().len() as u64
    }

    /// Flushes and syncs the partial file, and says how far it has got.
    pub fn progress(&mut self) -> Result<Progress, String> {
        let out = &mut self.out;
        out.flush().map_err(|e| fail(&self.path, e))?;
        let h = out.get_ref();
        h.file.sync_data().map_err(|e| fail(&self.path, e))?;
        Ok(Progress {
            len: h.len,
            hash: h.hash.clone().finalize(),
        })
    }

    pub fn fail(&self, e: std::io::Error) -> String {
        fail(&self.path, e)
    }

    /// Leaves the partial file for a resume (a checkpoint records its progress).
    pub fn keep(mut self) -> Result<(), String> {
        self.progress()?;
        self.partial
            .keep()
            .map(|_| ())
            .map_err(|e| fail(&self.path, e.error))
    }

    /// Renames the finished output into place. Should that fail, the partial file stays for a
    /// resume from the last checkpoint.
    pub fn commit(self) -> Result<(), String> {
        let Self { path, out, partial } = self;
        let hashed = match out.into_inner() {
            Ok(hashed) => hashed,
            Err(e) => {
                let _ = partial.keep();
                return Err(fail(&path, e.into_error()));
            }
        };
        crate::atomic::persist(&hashed.file, partial, &path, OnFailure::Keep)
    }
}

fn fail(path: &Path, e: std::io::Error) -> String {
    format!("cannot write {}: {e}", path.display())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("spheresweep-staged-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn a_reopened_output_cuts_what_came_after_its_checkpoint_and_appends() {
        let dir = scratch("reopen");
        let path = dir.join("out.txt");
        let mut a = Staged::create(path.clone()).unwrap();
        a.writer().write_all(b"first ").unwrap();
        let progress = a.progress().unwrap();
        assert_eq!(
            progress,
            Progress {
                len: 6,
                hash: hash::of(b"first ")
            }
        );
        a.writer().write_all(b"lost").unwrap();
        a.keep().unwrap();
        let mut b = Staged::reopen(path.clone(), progress).unwrap();
        b.writer().write_all(b"second").unwrap();
        assert_eq!(b.written(), 12);
        b.commit().unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"first second");
        assert!(!partial_path(&path).exists());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_partial_file_that_differs_is_refused_and_kept() {
        let dir = scratch("differs");
        let path = dir.join("out.txt");
        let mut a = Staged::create(path.clone()).unwrap();
        a.writer().write_all(b"0123456789").unwrap();
        let progress = a.progress().unwrap();
        a.keep().unwrap();
        std::fs::write(partial_path(&path), b"0123456780").unwrap();
        let err = Staged::reopen(path.clone(), progress).err().unwrap();
        assert!(err.contains("first 10 bytes differ"), "{err}");
        assert!(
            partial_path(&path).exists(),
            "a refused resume removed the partial file"
        );
        std::fs::write(partial_path(&path), b"01234").unwrap();
        let err = Staged::reopen(path.clone(), progress).err().unwrap();
        assert!(err.contains("holds 5 bytes, fewer than the 10"), "{err}");
        std::fs::remove_file(partial_path(&path)).unwrap();
        let err = Staged::reopen(path.clone(), progress).err().unwrap();
        assert!(err.contains("cannot be opened"), "{err}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
