//! Zarr v3 stores on a (shared) file system, through the `zarrs` crate (feature `zarr`):
//! chunked, zstd-compressed arrays with named dimensions and CF-style attributes, written by
//! any number of independent processes, read chunk by chunk.
//!
//! Principal types:
//! - [`ArraySpec`]: one array of a store (name, shape, chunk shape, dimension names, data
//!   type, attributes).
//! - [`Store`]: a store opened or created at a folder `NAME.zarr`. [`Store::create`] writes the
//!   root group's and every array's `zarr.json`, or, when they exist, checks that they are the
//!   same (so any number of writers may start in any order: whichever comes first writes the
//!   metadata, and a writer with other parameters is refused). [`Store::write_chunk_f32`] encodes
//!   and writes one chunk; [`Store::chunk_state`] tells whether a chunk is there and decodes;
//!   [`Store::read_chunk_f32`] reads one.
//! - [`AtomicFsStore`]: the `zarrs` file-system store with every write made atomic (a temporary
//!   sibling, `.NAME.tmp-PID`, renamed onto the key when complete; [`crate::engine::io`]), so a
//!   killed writer never leaves a half-written chunk or metadata document, only a temporary
//!   file that [`Store::stale_temporaries`] finds.
//!
//! Layout (Zarr v3 specification, <https://zarr-specs.readthedocs.io/en/latest/v3/core/index.html>):
//! `NAME.zarr/zarr.json` is the root group, with the global attributes and, as zarr-python
//! writes it, the `consolidated_metadata` of every array (so that `xarray.open_zarr(path)` reads
//! the store's metadata in one request); `NAME.zarr/ARRAY/zarr.json` an array, with
//! `dimension_names` (xarray's dimensions) and its attributes (`units`, `long_name`, ...);
//! chunk `(i, j)` of `ARRAY` is the file `NAME.zarr/ARRAY/c/i/j`. Float arrays have the fill
//! value NaN, so that xarray's CF decoding masks nothing but missing data.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde_json::{Map, Value};
use zarrs::array::{Array, ArrayBuilder, ZARR_NAN_F32, ZARR_NAN_F64, codec::ZstdCodec, data_type};
use zarrs::array::{ArrayBytes, CodecOptions};
use zarrs::filesystem::FilesystemStore;
use zarrs::group::GroupBuilder;
use zarrs::storage::byte_range::ByteRangeIterator;
use zarrs::storage::{
    Bytes, ListableStorageTraits, MaybeBytesIterator, OffsetBytesIterator, ReadableStorageTraits,
    StorageError, StoreKey, StoreKeys, StoreKeysPrefixes, StorePrefix, WritableStorageTraits,
};

/// Errors of a Zarr store.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum ZarrError {
    /// Reading or writing the store failed.
    #[error("{path}: {reason}")]
    Io {
        /// The store, array or chunk.
        path: String,
        /// What went wrong.
        reason: String,
    },
    /// The store exists with other metadata (other parameters, shape or version).
    #[error(
        "{path}: the store was made with other parameters ({reason}); write to a new store, or remove this one"
    )]
    Mismatch {
        /// The metadata document.
        path: String,
        /// What differs.
        reason: String,
    },
}

fn io(path: impl std::fmt::Display, e: impl std::fmt::Display) -> ZarrError {
    ZarrError::Io {
        path: path.to_string(),
        reason: crate::engine::io::short(&e.to_string()),
    }
}

/// Element type of an array.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dtype {
    /// 32-bit float (fill NaN).
    F32,
    /// 64-bit float (fill NaN).
    F64,
}

/// One array of a store.
#[derive(Clone, Debug, PartialEq)]
pub struct ArraySpec {
    /// The array's name (its folder in the store).
    pub name: String,
    /// Shape, slowest dimension first.
    pub shape: Vec<u64>,
    /// Chunk shape (regular grid; the last chunk along an axis is padded with NaN).
    pub chunks: Vec<u64>,
    /// Dimension names (xarray's `dims`).
    pub dims: Vec<String>,
    /// Element type.
    pub dtype: Dtype,
    /// Attributes (CF: `units`, `long_name`, `standard_name`, `axis`, ...).
    pub attrs: Map<String, Value>,
}

impl ArraySpec {
    /// A float32 data array `name(dims)` of `shape` in `chunks`, with CF `units` and
    /// `long_name` (and a `comment` when not empty).
    pub fn data_f32(
        name: &str,
        dims: &[&str],
        shape: &[usize],
        chunks: &[usize],
        (units, long): (&str, &str),
        comment: &str,
    ) -> ArraySpec {
        let mut a = attrs(&[("units", units), ("long_name", long)]);
        if !comment.is_empty() {
            a.insert("comment".into(), Value::from(comment));
        }
        ArraySpec {
            name: name.into(),
            shape: shape.iter().map(|&n| n as u64).collect(),
            chunks: chunks.iter().map(|&n| n as u64).collect(),
            dims: dims.iter().map(|d| d.to_string()).collect(),
            dtype: Dtype::F32,
            attrs: a,
        }
    }

    /// Chunks along each axis.
    pub fn grid(&self) -> Vec<u64> {
        self.shape
            .iter()
            .zip(&self.chunks)
            .map(|(&n, &c)| n.div_ceil(c.max(1)))
            .collect()
    }
}

/// The `zarrs` file-system store with atomic writes (module docs).
#[derive(Debug)]
pub struct AtomicFsStore {
    root: PathBuf,
    inner: FilesystemStore,
}

impl AtomicFsStore {
    /// The store at folder `root` (created if missing).
    pub fn new(root: &Path) -> Result<Self, ZarrError> {
        std::fs::create_dir_all(root).map_err(|e| io(root.display(), e))?;
        let inner = FilesystemStore::new(root).map_err(|e| io(root.display(), e))?;
        Ok(AtomicFsStore {
            root: root.to_path_buf(),
            inner,
        })
    }

    /// The file of `key`.
    pub fn key_path(&self, key: &StoreKey) -> PathBuf {
        self.root.join(key.as_str())
    }
}

impl ReadableStorageTraits for AtomicFsStore {
    fn get_partial_many<'a>(
        &'a self,
        key: &StoreKey,
        byte_ranges: ByteRangeIterator<'a>,
    ) -> Result<MaybeBytesIterator<'a>, StorageError> {
        self.inner.get_partial_many(key, byte_ranges)
    }
    fn size_key(&self, key: &StoreKey) -> Result<Option<u64>, StorageError> {
        self.inner.size_key(key)
    }
    fn supports_get_partial(&self) -> bool {
        self.inner.supports_get_partial()
    }
}

impl ListableStorageTraits for AtomicFsStore {
    fn list(&self) -> Result<StoreKeys, StorageError> {
        self.inner.list()
    }
    fn list_prefix(&self, prefix: &StorePrefix) -> Result<StoreKeys, StorageError> {
        self.inner.list_prefix(prefix)
    }
    fn list_dir(&self, prefix: &StorePrefix) -> Result<StoreKeysPrefixes, StorageError> {
        self.inner.list_dir(prefix)
    }
    fn size_prefix(&self, prefix: &StorePrefix) -> Result<u64, StorageError> {
        self.inner.size_prefix(prefix)
    }
}

impl WritableStorageTraits for AtomicFsStore {
    /// Writes `value` to a temporary sibling of the key's file and renames it onto the file.
    fn set(&self, key: &StoreKey, value: Bytes) -> Result<(), StorageError> {
        // (a run being interrupted writes nothing more: its temporary store is being removed)
        if crate::engine::io::interrupted() {
            return Err(StorageError::Other("the run was interrupted".into()));
        }
        let path = self.key_path(key);
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)?;
        }
        let tmp = crate::engine::io::TempFile::new(&path);
        std::fs::write(tmp.path(), &value)?;
        tmp.commit_now(&path)?;
        Ok(())
    }
    fn set_partial_many(
        &self,
        key: &StoreKey,
        offset_values: OffsetBytesIterator,
    ) -> Result<(), StorageError> {
        zarrs::storage::store_set_partial_many(self, key, offset_values)
    }
    fn erase(&self, key: &StoreKey) -> Result<(), StorageError> {
        self.inner.erase(key)
    }
    fn erase_prefix(&self, prefix: &StorePrefix) -> Result<(), StorageError> {
        self.inner.erase_prefix(prefix)
    }
    fn supports_set_partial(&self) -> bool {
        false
    }
}

/// Whether a chunk is complete.
#[derive(Clone, Debug, PartialEq)]
pub enum ChunkState {
    /// Present and decodes to the chunk's size.
    Ok,
    /// Not written yet.
    Missing,
    /// Present but does not decode (the reason).
    Damaged(String),
}

/// A Zarr v3 store (module docs).
pub struct Store {
    root: PathBuf,
    storage: Arc<AtomicFsStore>,
    arrays: Vec<(ArraySpec, Array<AtomicFsStore>)>,
}

impl std::fmt::Debug for Store {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Store")
            .field("root", &self.root)
            .field(
                "arrays",
                &self.arrays.iter().map(|a| &a.0.name).collect::<Vec<_>>(),
            )
            .finish()
    }
}

/// The zstd level of the chunks (1: fast; level 3 compresses mosaics a few per cent better at
/// about half the speed).
pub const ZSTD_LEVEL: i32 = 1;

fn build(
    storage: &Arc<AtomicFsStore>,
    spec: &ArraySpec,
) -> Result<Array<AtomicFsStore>, ZarrError> {
    let (dt, fill) = match spec.dtype {
        Dtype::F32 => (data_type::float32(), ZARR_NAN_F32.into()),
        Dtype::F64 => (data_type::float64(), ZARR_NAN_F64.into()),
    };
    let fill: zarrs::array::FillValueMetadata = fill;
    let mut b = ArrayBuilder::new(spec.shape.clone(), spec.chunks.clone(), dt, fill);
    b.bytes_to_bytes_codecs(vec![Arc::new(ZstdCodec::new(ZSTD_LEVEL, true))])
        .dimension_names(Some(spec.dims.clone()))
        .attributes(spec.attrs.clone());
    let path = format!("/{}", spec.name);
    let mut a = b
        .build(storage.clone(), &path)
        .map_err(|e| io(format!("{}/{}", storage.root.display(), spec.name), e))?;
    a.set_codec_options(CodecOptions::default().with_store_empty_chunks(true));
    Ok(a)
}

/// Writes the metadata document `rel` of the store at `root` when absent; when present,
/// checks that it says the same (the JSON values compared, whatever the formatting). With
/// `create` false an absent document is a mismatch too (nothing is written).
///
/// The document is created by a hard link of a finished temporary file, which fails when
/// another writer created it first: of writers that start at once with other metadata, exactly
/// one wins and the others are refused (a rename would let each replace the other's document
/// and go on writing chunks of other parameters into one store). A file system without hard
/// links falls back to the rename.
fn ensure_document(root: &Path, rel: &str, doc: &Value, create: bool) -> Result<(), ZarrError> {
    let path = root.join(rel);
    let compare = |bytes: &[u8]| {
        let old: Value = serde_json::from_slice(bytes).map_err(|e| io(path.display(), e))?;
        if &old != doc {
            return Err(ZarrError::Mismatch {
                path: path.display().to_string(),
                reason: describe_difference(&old, doc),
            });
        }
        Ok(())
    };
    match std::fs::read(&path) {
        Ok(bytes) => compare(&bytes),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound && !create => Err(ZarrError::Mismatch {
            path: path.display().to_string(),
            reason: format!("no {rel}"),
        }),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            if let Some(d) = path.parent() {
                std::fs::create_dir_all(d).map_err(|e| io(d.display(), e))?;
            }
            let text = serde_json::to_vec_pretty(doc).map_err(|e| io(path.display(), e))?;
            // (a temporary of its own, `.zarr.json.N.tmp-PID`, also among this process's
            // threads)
            static N: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
            let n = N.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            let name = path
                .file_name()
                .map_or("zarr.json".into(), |f| f.to_string_lossy());
            let tmp = crate::engine::io::TempFile::new(&path.with_file_name(format!("{name}.{n}")));
            std::fs::write(tmp.path(), &text).map_err(|e| io(path.display(), e))?;
            match std::fs::hard_link(tmp.path(), &path) {
                // (the temporary name is removed when `tmp` is dropped)
                Ok(()) => Ok(()),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    let bytes = std::fs::read(&path).map_err(|e| io(path.display(), e))?;
                    compare(&bytes)
                }
                Err(_) => tmp.commit_now(&path).map_err(|e| io(path.display(), e)),
            }
        }
        Err(e) => Err(io(path.display(), e)),
    }
}

/// The first few attributes or fields that differ between two metadata documents.
fn describe_difference(old: &Value, new: &Value) -> String {
    fn walk(prefix: &str, a: &Value, b: &Value, out: &mut Vec<String>) {
        match (a, b) {
            (Value::Object(x), Value::Object(y)) => {
                let keys: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
                for k in keys {
                    let p = if prefix.is_empty() {
                        k.clone()
                    } else {
                        format!("{prefix}.{k}")
                    };
                    match (x.get(k), y.get(k)) {
                        (Some(u), Some(v)) => walk(&p, u, v, out),
                        (u, v) => out.push(format!(
                            "{p}: {} in the store, {} now",
                            u.map_or("absent".into(), |u| u.to_string()),
                            v.map_or("absent".into(), |v| v.to_string())
                        )),
                    }
                }
            }
            _ if a != b => out.push(format!("{prefix}: {a} in the store, {b} now")),
            _ => {}
        }
    }
    let mut out = Vec::new();
    walk("", old, new, &mut out);
    out.truncate(3);
    crate::engine::io::short(&out.join("; "))
}

impl Store {
    /// Creates the store at `root` with the group attributes `attrs` and `arrays`, or opens it
    /// when a writer has created it already with the same metadata (module docs). Errors: the
    /// store exists with other metadata ([`ZarrError::Mismatch`]), or I/O.
    pub fn create(
        root: &Path,
        attrs: Map<String, Value>,
        arrays: Vec<ArraySpec>,
    ) -> Result<Store, ZarrError> {
        Store::with_metadata(root, attrs, arrays, true)
    }

    /// Checks, writing nothing, that the existing store at `root` has the metadata that
    /// [`Store::create`] would give it: the group attributes `attrs` and `arrays`. Errors: a
    /// metadata document that differs or is absent ([`ZarrError::Mismatch`], naming what
    /// differs), or I/O.
    pub fn matches(
        root: &Path,
        attrs: Map<String, Value>,
        arrays: Vec<ArraySpec>,
    ) -> Result<(), ZarrError> {
        if !root.join("zarr.json").is_file() {
            return Err(io(root.display(), "not a Zarr v3 store (no zarr.json)"));
        }
        Store::with_metadata(root, attrs, arrays, false).map(|_| ())
    }

    fn with_metadata(
        root: &Path,
        attrs: Map<String, Value>,
        arrays: Vec<ArraySpec>,
        create: bool,
    ) -> Result<Store, ZarrError> {
        let storage = Arc::new(AtomicFsStore::new(root)?);
        let mut built = Vec::new();
        let mut consolidated = Map::new();
        for spec in arrays {
            let a = build(&storage, &spec)?;
            let meta = serde_json::to_value(a.metadata()).map_err(|e| io(root.display(), e))?;
            consolidated.insert(spec.name.clone(), meta);
            built.push((spec, a));
        }
        let group = GroupBuilder::new()
            .attributes(attrs)
            .build(storage.clone(), "/")
            .map_err(|e| io(root.display(), e))?;
        let mut gmeta =
            serde_json::to_value(group.metadata()).map_err(|e| io(root.display(), e))?;
        if let Value::Object(m) = &mut gmeta {
            m.insert(
                "consolidated_metadata".into(),
                serde_json::json!({
                    "kind": "inline",
                    "must_understand": false,
                    "metadata": Value::Object(consolidated.clone()),
                }),
            );
        }
        if create {
            // the arrays first, then the group: a store whose root document exists is complete
            for (name, meta) in &consolidated {
                ensure_document(root, &format!("{name}/zarr.json"), meta, true)?;
            }
            ensure_document(root, "zarr.json", &gmeta, true)?;
        } else {
            // the group first: it holds the attributes (the parameters), and every array's
            // metadata besides
            ensure_document(root, "zarr.json", &gmeta, false)?;
            for (name, meta) in &consolidated {
                ensure_document(root, &format!("{name}/zarr.json"), meta, false)?;
            }
        }
        Ok(Store {
            root: root.to_path_buf(),
            storage,
            arrays: built,
        })
    }

    /// Opens an existing store: its root group and every array it lists.
    pub fn open(root: &Path) -> Result<Store, ZarrError> {
        let text = std::fs::read(root.join("zarr.json")).map_err(|e| {
            io(
                root.display(),
                format!("not a Zarr v3 store (no readable zarr.json: {e})"),
            )
        })?;
        let group: Value = serde_json::from_slice(&text).map_err(|e| io(root.display(), e))?;
        if group.get("zarr_format") != Some(&Value::from(3)) {
            return Err(io(
                root.display(),
                "not a Zarr v3 store (zarr_format is not 3)",
            ));
        }
        let storage = Arc::new(AtomicFsStore::new(root)?);
        let mut names: Vec<String> = match group
            .get("consolidated_metadata")
            .and_then(|c| c.get("metadata"))
            .and_then(Value::as_object)
        {
            Some(m) => m.keys().cloned().collect(),
            None => std::fs::read_dir(root)
                .map_err(|e| io(root.display(), e))?
                .filter_map(|e| e.ok())
                .filter(|e| e.path().join("zarr.json").is_file())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect(),
        };
        names.sort();
        let mut arrays = Vec::new();
        for name in names {
            let a = Array::open(storage.clone(), &format!("/{name}"))
                .map_err(|e| io(format!("{}/{name}", root.display()), e))?;
            let dtype = if a.data_type() == &data_type::float32() {
                Dtype::F32
            } else if a.data_type() == &data_type::float64() {
                Dtype::F64
            } else {
                continue;
            };
            let chunks = a
                .chunk_shape(&vec![0; a.dimensionality()])
                .map_err(|e| io(format!("{}/{name}", root.display()), e))?
                .iter()
                .map(|c| c.get())
                .collect();
            let spec = ArraySpec {
                name: name.clone(),
                shape: a.shape().to_vec(),
                chunks,
                dims: a
                    .dimension_names()
                    .as_ref()
                    .map(|d| {
                        d.iter()
                            .map(|n| n.clone().unwrap_or_default())
                            .collect::<Vec<_>>()
                    })
                    .unwrap_or_default(),
                dtype,
                attrs: a.attributes().clone(),
            };
            arrays.push((spec, a));
        }
        Ok(Store {
            root: root.to_path_buf(),
            storage,
            arrays,
        })
    }

    /// The store's folder.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// The root group's attributes.
    pub fn attributes(&self) -> Result<Map<String, Value>, ZarrError> {
        let path = self.root.join("zarr.json");
        let text = std::fs::read(&path).map_err(|e| io(path.display(), e))?;
        let v: Value = serde_json::from_slice(&text).map_err(|e| io(path.display(), e))?;
        Ok(v.get("attributes")
            .and_then(Value::as_object)
            .cloned()
            .unwrap_or_default())
    }

    /// The arrays' specifications.
    pub fn arrays(&self) -> impl Iterator<Item = &ArraySpec> {
        self.arrays.iter().map(|a| &a.0)
    }

    /// The array called `name`, if any.
    pub fn spec(&self, name: &str) -> Option<&ArraySpec> {
        self.arrays().find(|a| a.name == name)
    }

    fn array(&self, name: &str) -> Result<&Array<AtomicFsStore>, ZarrError> {
        self.arrays
            .iter()
            .find(|a| a.0.name == name)
            .map(|a| &a.1)
            .ok_or_else(|| io(self.root.display(), format!("no array '{name}'")))
    }

    /// The file of chunk `idx` of array `name`.
    pub fn chunk_path(&self, name: &str, idx: &[u64]) -> Result<PathBuf, ZarrError> {
        let a = self.array(name)?;
        Ok(self.storage.key_path(&a.chunk_key(idx)))
    }

    /// Encodes `data` (the whole chunk, C order, NaN in the padding beyond the array's edge)
    /// and writes chunk `idx` of array `name` atomically.
    pub fn write_chunk_f32(&self, name: &str, idx: &[u64], data: &[f32]) -> Result<(), ZarrError> {
        self.array(name)?
            .store_chunk(idx, data)
            .map_err(|e| io(format!("{}/{name} chunk {idx:?}", self.root.display()), e))
    }

    /// [`Store::write_chunk_f32`] for a 64-bit array.
    pub fn write_chunk_f64(&self, name: &str, idx: &[u64], data: &[f64]) -> Result<(), ZarrError> {
        self.array(name)?
            .store_chunk(idx, data)
            .map_err(|e| io(format!("{}/{name} chunk {idx:?}", self.root.display()), e))
    }

    /// Reads chunk `idx` of the 32-bit array `name` (NaN where never written).
    pub fn read_chunk_f32(&self, name: &str, idx: &[u64]) -> Result<Vec<f32>, ZarrError> {
        self.array(name)?
            .retrieve_chunk::<Vec<f32>>(idx)
            .map_err(|e| io(format!("{}/{name} chunk {idx:?}", self.root.display()), e))
    }

    /// Reads chunk `idx` of the 64-bit array `name`.
    pub fn read_chunk_f64(&self, name: &str, idx: &[u64]) -> Result<Vec<f64>, ZarrError> {
        self.array(name)?
            .retrieve_chunk::<Vec<f64>>(idx)
            .map_err(|e| io(format!("{}/{name} chunk {idx:?}", self.root.display()), e))
    }

    /// Whether chunk `idx` of array `name` is present and decodes (its zstd checksum and
    /// size).
    pub fn chunk_state(&self, name: &str, idx: &[u64]) -> Result<ChunkState, ZarrError> {
        let a = self.array(name)?;
        let key = a.chunk_key(idx);
        match self.storage.size_key(&key) {
            Ok(None) => return Ok(ChunkState::Missing),
            Ok(Some(_)) => {}
            Err(e) => return Ok(ChunkState::Damaged(e.to_string())),
        }
        let r: Result<ArrayBytes<'static>, _> = a.retrieve_chunk(idx);
        Ok(match r {
            Ok(_) => ChunkState::Ok,
            Err(e) => ChunkState::Damaged(crate::engine::io::short(&e.to_string())),
        })
    }

    /// Temporary files left by killed writers (`.NAME.tmp-PID` anywhere in the store).
    pub fn stale_temporaries(&self) -> Vec<PathBuf> {
        let mut out = Vec::new();
        let mut stack = vec![self.root.clone()];
        while let Some(d) = stack.pop() {
            let Ok(rd) = std::fs::read_dir(&d) else {
                continue;
            };
            for e in rd.flatten() {
                let p = e.path();
                if e.file_type().is_ok_and(|t| t.is_dir()) {
                    stack.push(p);
                } else if is_temporary(&p) {
                    out.push(p);
                }
            }
        }
        out.sort();
        out
    }
}

/// Whether `p` is a temporary file of [`crate::engine::io::temp_path`] (`.NAME.tmp-PID`).
pub fn is_temporary(p: &Path) -> bool {
    p.file_name()
        .map(|n| n.to_string_lossy())
        .is_some_and(|n| n.starts_with('.') && n.contains(".tmp-"))
}

/// Removes the temporary files `.NAME.tmp-PID` in folder `dir` left by killed writers (any
/// other process) for the file names `NAME` that `mine` accepts; returns how many.
pub fn remove_temporaries_in(dir: &Path, mine: impl Fn(&str) -> bool) -> usize {
    let me = format!(".tmp-{}", std::process::id());
    let mut n = 0;
    if let Ok(rd) = std::fs::read_dir(dir) {
        for e in rd.flatten() {
            let f = e.file_name().to_string_lossy().into_owned();
            let Some((name, _)) = f.strip_prefix('.').and_then(|r| r.rsplit_once(".tmp-")) else {
                continue;
            };
            if !f.ends_with(&me) && mine(name) && std::fs::remove_file(e.path()).is_ok() {
                n += 1;
            }
        }
    }
    n
}

/// A TOML value (a scenario parameter) as a JSON attribute value: numbers stay numbers,
/// non-finite floats and arrays or tables become their text.
pub fn toml_to_json(v: &toml::Value) -> Value {
    match v {
        toml::Value::String(s) => Value::String(s.clone()),
        toml::Value::Integer(i) => Value::from(*i),
        toml::Value::Float(f) if f.is_finite() => Value::from(*f),
        toml::Value::Float(f) => Value::String(f.to_string()),
        toml::Value::Boolean(b) => Value::Bool(*b),
        other => Value::String(other.to_string()),
    }
}
/// What is at a store's path before a run writes it: `None` nothing (a new store), `Some(true)`
/// a store (a folder with a `zarr.json`), `Some(false)` a folder that is not one. Refused, with
/// the reason: a folder above it that does not exist, a symbolic link, anything but a folder.
pub fn store_target(path: &Path) -> Result<Option<bool>, String> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return Err(format!("the folder {} does not exist", dir.display()));
    }
    // (a folder that takes no new entry is refused before the run, not at its end)
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
    let probe = dir.join(format!(
        ".{}.probe-{}",
        name.unwrap_or_else(|| "store".into()),
        std::process::id()
    ));
    match std::fs::create_dir(&probe) {
        Ok(()) => {
            let _ = std::fs::remove_dir(&probe);
        }
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
        Err(e) => {
            return Err(format!(
                "its folder {} cannot be written ({e})",
                dir.display()
            ));
        }
    }
    match std::fs::symlink_metadata(path) {
        Err(_) => Ok(None),
        Ok(m) if m.file_type().is_symlink() => {
            Err("is a symbolic link; give the folder it points to".into())
        }
        Ok(m) if !m.is_dir() => Err(
            "exists and is not a folder (a Zarr store is a folder); remove it or choose another \
             name"
                .into(),
        ),
        Ok(_) => Ok(Some(path.join("zarr.json").is_file())),
    }
}

/// Writes a whole store at `root` as one output: `fill` writes it into a temporary sibling
/// folder (`.NAME.tmp-PID`), which replaces `root` only when `fill` succeeded, so a reader
/// never sees a half-written store. An existing `root` must itself be a Zarr store (it has a
/// `zarr.json`); any other folder or file there is refused, never deleted. On error the
/// temporary folder is removed and `root` is left as it was.
pub fn replace_store<F>(root: &Path, fill: F) -> Result<(), ZarrError>
where
    F: FnOnce(&Path) -> Result<(), ZarrError>,
{
    let parent = match root.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !parent.is_dir() {
        return Err(io(root.display(), "the folder does not exist"));
    }
    match std::fs::symlink_metadata(root) {
        Ok(m) if m.is_dir() && root.join("zarr.json").is_file() => {}
        Ok(_) => {
            return Err(io(
                root.display(),
                "exists and is not a Zarr store; remove it or choose another name",
            ));
        }
        Err(_) => {}
    }
    let tmp = crate::engine::io::temp_path(root);
    let _ = std::fs::remove_dir_all(&tmp);
    let guard = crate::engine::io::TempFile::new(root);
    let result = fill(&tmp).and_then(|()| {
        // (an existing store is moved aside, replaced and then removed)
        crate::engine::io::publish(&tmp, root).map_err(|e| io(root.display(), e))
    });
    if result.is_err() {
        let _ = std::fs::remove_dir_all(&tmp);
    }
    drop(guard);
    result
}

/// Attributes from `(name, value)` pairs of strings.
pub fn attrs(pairs: &[(&str, &str)]) -> Map<String, Value> {
    pairs
        .iter()
        .map(|(k, v)| (k.to_string(), Value::String(v.to_string())))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("cellsurf-zarr-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    fn spec() -> ArraySpec {
        ArraySpec {
            name: "a".into(),
            shape: vec![5, 4],
            chunks: vec![2, 4],
            dims: vec!["y".into(), "x".into()],
            dtype: Dtype::F32,
            attrs: attrs(&[("units", "m")]),
        }
    }

    #[test]
    fn of_writers_starting_at_once_with_other_metadata_exactly_one_wins() {
        // each thread creates the store with its own title, all released at once: whoever
        // creates the root document first wins, every other one is refused (none replaces it)
        let d = dir("race").join("s.zarr");
        let n = 8;
        let gate = Arc::new(std::sync::Barrier::new(n));
        let handles: Vec<_> = (0..n)
            .map(|i| {
                let (d, gate) = (d.clone(), gate.clone());
                std::thread::spawn(move || {
                    gate.wait();
                    Store::create(&d, attrs(&[("title", &format!("t{i}"))]), vec![spec()])
                        .map(|_| i)
                })
            })
            .collect();
        let results: Vec<_> = handles.into_iter().map(|h| h.join().unwrap()).collect();
        let won: Vec<usize> = results.iter().filter_map(|r| r.clone().ok()).collect();
        assert_eq!(won.len(), 1, "{results:?}");
        for e in results.iter().filter_map(|r| r.clone().err()) {
            assert!(matches!(e, ZarrError::Mismatch { .. }), "{e}");
        }
        let o = Store::open(&d).unwrap();
        assert_eq!(o.attributes().unwrap()["title"], format!("t{}", won[0]));
        // checked without writing: the same metadata matches, other metadata is named
        Store::matches(
            &d,
            attrs(&[("title", &format!("t{}", won[0]))]),
            vec![spec()],
        )
        .unwrap();
        let e = Store::matches(&d, attrs(&[("title", "x")]), vec![spec()]).unwrap_err();
        assert!(e.to_string().contains("attributes.title"), "{e}");
        std::fs::remove_dir_all(d.parent().unwrap()).unwrap();
    }

    #[test]
    fn chunks_round_trip_and_metadata_is_checked() {
        let d = dir("rt").join("s.zarr");
        let s = Store::create(&d, attrs(&[("title", "t")]), vec![spec()]).unwrap();
        assert_eq!(s.chunk_state("a", &[0, 0]).unwrap(), ChunkState::Missing);
        let data: Vec<f32> = (0..8).map(|v| v as f32).collect();
        s.write_chunk_f32("a", &[1, 0], &data).unwrap();
        assert_eq!(s.chunk_state("a", &[1, 0]).unwrap(), ChunkState::Ok);
        assert_eq!(s.read_chunk_f32("a", &[1, 0]).unwrap(), data);
        assert!(s.stale_temporaries().is_empty());
        // a second writer with the same metadata opens it; one with other attributes is refused
        Store::create(&d, attrs(&[("title", "t")]), vec![spec()]).unwrap();
        let e = Store::create(&d, attrs(&[("title", "u")]), vec![spec()]).unwrap_err();
        assert!(e.to_string().contains("attributes.title"), "{e}");
        // reopened from disk: the same arrays
        let o = Store::open(&d).unwrap();
        assert_eq!(o.spec("a"), Some(&spec()));
        assert_eq!(o.attributes().unwrap()["title"], "t");
        // a damaged chunk is found
        let p = s.chunk_path("a", &[1, 0]).unwrap();
        let mut b = std::fs::read(&p).unwrap();
        let n = b.len();
        b[n / 2] ^= 0xff;
        std::fs::write(&p, &b).unwrap();
        assert!(matches!(
            o.chunk_state("a", &[1, 0]).unwrap(),
            ChunkState::Damaged(_)
        ));
        // a temporary file left behind is found, and removed for its chunk
        let t = p.parent().unwrap().join(".0.tmp-999999");
        std::fs::write(&t, b"x").unwrap();
        assert_eq!(o.stale_temporaries(), vec![t.clone()]);
        assert_eq!(remove_temporaries_in(p.parent().unwrap(), |n| n == "1"), 0);
        assert_eq!(remove_temporaries_in(p.parent().unwrap(), |n| n == "0"), 1);
        assert!(!t.exists());
        std::fs::remove_dir_all(d.parent().unwrap()).unwrap();
    }
}
