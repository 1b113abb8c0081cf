//! Fabrications kept in memory for download: each bundle's files and a zip of them all, under an id
//! nobody can guess. The store is bounded in count and bytes; the oldest bundle goes first.

use axum::body::Bytes;
use linkwright_core::fab::is_safe_relative_path;
use std::collections::hash_map::RandomState;
use std::collections::VecDeque;
use std::hash::BuildHasher;
use std::io::Write;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

/// The name of the zip of every file, beside the bundle's own files (none of which sits at the top
/// level under this name).
pub(super) const ZIP_NAME: &str = "fabrication.zip";

/// How much the store keeps.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Limits {
    /// Bundles kept. Default 8.
    pub count: usize,
    /// Bytes kept, over every bundle's files and zip. Default 256 MiB. The newest bundle is kept even
    /// when it alone is larger.
    pub bytes: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits { count: 8, bytes: 256 * 1024 * 1024 }
    }
}

/// One fabrication's downloads.
#[derive(Debug)]
pub(crate) struct Stored {
    /// File-name-safe name of the scene, for the zip's download name.
    pub scene: String,
    /// `(relative path, contents)`, in the bundle's order.
    pub files: Vec<(String, Bytes)>,
    pub zip: Bytes,
}

impl Stored {
    /// The bundle's files and their zip.
    pub(crate) fn new(scene: String, files: Vec<(String, Vec<u8>)>) -> Result<Stored, String> {
        let zip = zip_of(&files).map_err(|e| format!("cannot write the zip of the files: {e}"))?;
        let files = files.into_iter().map(|(path, bytes)| (path, Bytes::from(bytes))).collect();
        Ok(Stored { scene, files, zip: Bytes::from(zip) })
    }

    fn bytes(&self) -> usize {
        self.zip.len() + self.files.iter().map(|(_, b)| b.len()).sum::<usize>()
    }

    /// The file at `path` (or the zip), with the name to save it under.
    pub(crate) fn file(&self, path: &str) -> Option<(String, Bytes)> {
        if path == ZIP_NAME {
            return Some((format!("{}-fabrication.zip", self.scene), self.zip.clone()));
        }
        let (_, bytes) = self.files.iter().find(|(p, _)| p == path)?;
        let name = path.rsplit('/').next().unwrap_or(path).to_string();
        Some((name, bytes.clone()))
    }
}

/// Every file in one zip, under the same relative paths, compressed. A path that is not a plain
/// relative one (`..`, absolute, a backslash) is refused: unzipping must never write outside the folder.
fn zip_of(files: &[(String, Vec<u8>)]) -> zip::result::ZipResult<Vec<u8>> {
    let mut z = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    for (path, bytes) in files {
        if !is_safe_relative_path(path) {
            let refused = std::io::Error::new(std::io::ErrorKind::InvalidInput, format!("unsafe entry name {path:?}"));
            return Err(zip::result::ZipError::Io(refused));
        }
        z.start_file(path.as_str(), options)?;
        z.write_all(bytes)?;
    }
    Ok(z.finish()?.into_inner())
}

/// The media type of a bundle file, by extension.
pub(super) fn media_type(path: &str) -> &'static str {
    match path.rsplit('.').next().unwrap_or("") {
        "stl" => "model/stl",
        "3mf" => "model/3mf",
        "svg" => "image/svg+xml",
        "dxf" => "image/vnd.dxf",
        "json" => "application/json",
        "zip" => "application/zip",
        _ => "application/octet-stream",
    }
}

/// The store.
#[derive(Debug)]
pub(crate) struct Bundles {
    limits: Limits,
    kept: Mutex<VecDeque<(String, Arc<Stored>)>>,
    counter: AtomicU64,
    /// Random keys of this process, so ids cannot be guessed from one another.
    keys: RandomState,
}

impl Bundles {
    pub(crate) fn new(limits: Limits) -> Bundles {
        Bundles { limits, kept: Mutex::default(), counter: AtomicU64::new(0), keys: RandomState::new() }
    }

    pub(crate) fn limits(&self) -> Limits {
        self.limits
    }

    /// Keeps `stored`, forgetting the oldest bundles beyond the limits; returns its id and itself.
    pub(crate) fn insert(&self, stored: Stored) -> (String, Arc<Stored>) {
        let n = self.counter.fetch_add(1, Ordering::Relaxed);
        let id = format!("{:016x}{n:x}", self.keys.hash_one(n));
        // A poisoned lock only means another request panicked mid-insert; the queue is still whole.
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        let stored = Arc::new(stored);
        kept.push_back((id.clone(), stored.clone()));
        let mut total: usize = kept.iter().map(|(_, s)| s.bytes()).sum();
        while kept.len() > 1 && (kept.len() > self.limits.count || total > self.limits.bytes) {
            if let Some((_, old)) = kept.pop_front() {
                total -= old.bytes();
            }
        }
        (id, stored)
    }

    /// The bundle `id`, while it is kept.
    pub(crate) fn get(&self, id: &str) -> Option<Arc<Stored>> {
        let kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        kept.iter().find(|(k, _)| k == id).map(|(_, s)| s.clone())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    fn stored(size: usize) -> Stored {
        let files = vec![("parts/a.stl".to_string(), vec![1; size]), ("fabrication.json".to_string(), b"{}".to_vec())];
        Stored::new("truck".into(), files).unwrap()
    }

    #[test]
    fn the_oldest_bundles_go_first() {
        let bundles = Bundles::new(Limits { count: 2, bytes: 1 << 20 });
        let ids: Vec<String> = (0..3).map(|_| bundles.insert(stored(10)).0).collect();
        assert!(bundles.get(&ids[0]).is_none());
        assert!(bundles.get(&ids[1]).is_some() && bundles.get(&ids[2]).is_some());
        assert_ne!(ids[1], ids[2]);

        let small = Bundles::new(Limits { count: 8, bytes: 3000 });
        let (first, _) = small.insert(stored(2000));
        let (second, _) = small.insert(stored(2000));
        assert!(small.get(&first).is_none(), "over the byte limit");
        assert!(small.get(&second).is_some(), "the newest is kept even alone over the limit");
    }

    #[test]
    fn entries_that_would_leave_the_folder_are_refused() {
        for path in ["parts/../../../../ESCAPED.stl", "/etc/passwd", "parts\\..\\x.stl", ".hidden"] {
            let files = vec![(path.to_string(), vec![1, 2, 3])];
            assert!(Stored::new("truck".into(), files).is_err(), "{path}");
        }
    }

    #[test]
    fn files_and_the_zip_are_served_by_path() {
        let s = stored(100);
        let (name, bytes) = s.file("parts/a.stl").unwrap();
        assert_eq!((name.as_str(), bytes.len()), ("a.stl", 100));
        assert!(s.file("parts/b.stl").is_none() && s.file("../a.stl").is_none());
        let (name, zip) = s.file(ZIP_NAME).unwrap();
        assert_eq!(name, "truck-fabrication.zip");
        let mut archive = zip::ZipArchive::new(std::io::Cursor::new(zip.to_vec())).unwrap();
        let mut json = String::new();
        archive.by_name("fabrication.json").unwrap().read_to_string(&mut json).unwrap();
        assert_eq!(json, "{}");
        assert_eq!(archive.len(), 2);
        assert_eq!(media_type("parts/a.stl"), "model/stl");
        assert_eq!(media_type(ZIP_NAME), "application/zip");
    }
}
