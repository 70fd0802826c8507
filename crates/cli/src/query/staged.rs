//! Outputs that appear whole or not at all: a file written under a temporary name beside its
//! final path, or a directory of column files built as a temporary directory, renamed into
//! place when complete and removed if dropped before that (a failed query leaves nothing).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use super::layout::OutColumn;

use crate::output::{set_aside, temporary};

fn fail(path: &Path) -> impl Fn(std::io::Error) -> String + '_ {
    move |e| format!("cannot write {}: {e}", path.display())
}

/// A file written under a temporary name, renamed to `path` by [`StagedFile::commit`].
#[derive(Debug)]
pub struct StagedFile {
    path: PathBuf,
    tmp: PathBuf,
    file: Option<File>,
}

impl StagedFile {
    /// Creates the temporary file (checked with `output::check_writable` first).
    pub fn create(path: &Path) -> Result<Self, String> {
        crate::output::check_writable(path)?;
        let tmp = temporary(path);
        let file = File::create(&tmp).map_err(fail(path))?;
        Ok(Self {
            path: path.to_path_buf(),
            tmp,
            file: Some(file),
        })
    }

    /// The final path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// A buffered writer on the temporary file (a second handle on it).
    pub fn writer(&self) -> Result<BufWriter<File>, String> {
        let file = self.file.as_ref().ok_or("staged file already committed")?;
        let clone = file.try_clone().map_err(fail(&self.path))?;
        Ok(BufWriter::with_capacity(1 << 20, clone))
    }

    /// A message for an error while writing.
    pub fn error(&self, e: impl std::fmt::Display) -> String {
        format!("cannot write {}: {e}", self.path.display())
    }

    /// Flushes to disk and renames into place (every writer must have been flushed).
    pub fn commit(mut self) -> Result<(), String> {
        let file = self.file.take().ok_or("staged file already committed")?;
        file.sync_all().map_err(fail(&self.path))?;
        drop(file);
        std::fs::rename(&self.tmp, &self.path).map_err(fail(&self.path))
    }
}

impl Drop for StagedFile {
    fn drop(&mut self) {
        if self.file.take().is_some() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// A directory of `.npy` columns built under a temporary name and swapped into place by
/// [`StagedDir::commit`]. An existing directory at the path is replaced only if it holds
/// nothing but column files a query writes (an earlier result); anything else is refused
/// before any work.
#[derive(Debug)]
pub struct StagedDir {
    path: PathBuf,
    tmp: PathBuf,
    open: bool,
}

impl StagedDir {
    /// Checks the path and creates the temporary directory.
    pub fn create(path: &Path) -> Result<Self, String> {
        if path.file_name().is_none() {
            return Err(format!(
                "cannot write {}: no directory name",
                path.display()
            ));
        }
        if path.exists() {
            if !path.is_dir() {
                return Err(format!(
                    "cannot write {}: it exists and is not a directory (results in .npy \
                     columns go to a directory)",
                    path.display()
                ));
            }
            let entries = std::fs::read_dir(path).map_err(fail(path))?;
            for entry in entries {
                let entry = entry.map_err(fail(path))?;
                let name = entry.file_name().to_string_lossy().into_owned();
                let ours = OutColumn::ALL
                    .iter()
                    .any(|c| name == format!("{}.npy", c.name()));
                if !ours || !entry.path().is_file() {
                    return Err(format!(
                        "cannot write {}: the directory holds {name}, which is not a result \
                         column; give a new directory (an earlier result is replaced whole)",
                        path.display()
                    ));
                }
            }
        }
        if let Some(parent) = path.parent()
            && !parent.as_os_str().is_empty()
        {
            std::fs::create_dir_all(parent).map_err(fail(path))?;
        }
        crate::output::remove_stale_temporaries(std::slice::from_ref(&path.to_path_buf()));
        let tmp = temporary(path);
        let _ = std::fs::remove_dir_all(&tmp);
        std::fs::create_dir(&tmp).map_err(fail(path))?;
        Ok(Self {
            path: path.to_path_buf(),
            tmp,
            open: true,
        })
    }

    /// The final path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Creates column file `name` in the temporary directory.
    pub fn create_file(&self, name: &str) -> Result<File, String> {
        File::create(self.tmp.join(name)).map_err(fail(&self.path))
    }

    /// A message for an error while writing.
    pub fn error(&self, e: impl std::fmt::Display) -> String {
        format!("cannot write {}: {e}", self.path.display())
    }

    /// Renames the finished directory into place (the files must have been synced). An
    /// earlier result at the path is moved aside first and removed after.
    pub fn commit(mut self) -> Result<(), String> {
        let old = set_aside(&self.path);
        let had_old = self.path.exists();
        if had_old {
            let _ = std::fs::remove_dir_all(&old);
            std::fs::rename(&self.path, &old).map_err(fail(&self.path))?;
        }
        if let Err(e) = std::fs::rename(&self.tmp, &self.path) {
            if had_old {
                let _ = std::fs::rename(&old, &self.path);
            }
            return Err(fail(&self.path)(e));
        }
        self.open = false;
        if had_old {
            let _ = std::fs::remove_dir_all(&old);
        }
        if let Ok(dir) = File::open(&self.path) {
            let _ = dir.sync_all();
        }
        Ok(())
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        if self.open {
            let _ = std::fs::remove_dir_all(&self.tmp);
        }
    }
}

/// Flushes a buffered writer and syncs its file.
pub fn finish_writer(
    mut w: BufWriter<File>,
    error: impl Fn(std::io::Error) -> String,
) -> Result<(), String> {
    w.flush().map_err(&error)?;
    let file = w.into_inner().map_err(|e| error(e.into_error()))?;
    file.sync_all().map_err(error)
}
