//! Where a library's bytes live: a read-only memory map of the file, or an owned buffer aligned
//! to 256 bytes (a plain read, or a decoded zstd section). This file holds the only `unsafe`
//! code of the crate.
//!
//! A map shares pages with the file. If another process truncates the file while it is mapped,
//! touching a page past the new end kills this process with SIGBUS; no check here can prevent
//! that. The writer never rewrites in place (it renames a new file over the old one, and a map
//! of the old file keeps the old pages), so this only happens when someone else edits the file.
//! Use [`super::Library::read`] for files that may change underneath the reader.

use std::fs::File;
use std::io::Read;
use std::path::Path;

use zerocopy::{FromBytes, Immutable, IntoBytes, KnownLayout};

use super::error::{FormatError, FormatResult};
use super::spec::{HEADER_SIZE, MAGIC};

/// Alignment of owned buffers: the section alignment of version 1.0 files, so that every
/// section of a file read into a buffer has the same alignment as in a map.
pub(crate) const BUFFER_ALIGNMENT: usize = 256;

#[derive(Clone, Copy, FromBytes, IntoBytes, KnownLayout, Immutable)]
#[repr(C, align(256))]
struct Block([u8; BUFFER_ALIGNMENT]);

/// Heap bytes whose start is aligned to [`BUFFER_ALIGNMENT`].
#[derive(Clone)]
pub(crate) struct AlignedBuf {
    blocks: Vec<Block>,
    len: usize,
}

impl std::fmt::Debug for AlignedBuf {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "AlignedBuf({} bytes)", self.len)
    }
}

impl AlignedBuf {
    /// A zero-filled buffer of `len` bytes.
    pub fn zeroed(len: usize) -> AlignedBuf {
        let blocks = vec![Block([0; BUFFER_ALIGNMENT]); len.div_ceil(BUFFER_ALIGNMENT)];
        AlignedBuf { blocks, len }
    }

    /// A copy of `bytes` in an aligned buffer.
    pub fn copy_from(bytes: &[u8]) -> AlignedBuf {
        let mut buf = AlignedBuf::zeroed(bytes.len());
        buf.bytes_mut().copy_from_slice(bytes);
        buf
    }

    pub fn bytes(&self) -> &[u8] {
        self.blocks.as_bytes().get(..self.len).unwrap_or_default()
    }

    pub fn bytes_mut(&mut self) -> &mut [u8] {
        self.blocks
            .as_mut_bytes()
            .get_mut(..self.len)
            .unwrap_or_default()
    }
}

/// The bytes of a whole library file.
pub(crate) enum Backing {
    /// A read-only shared map of the file.
    Mapped(memmap2::Mmap),
    /// A copy in memory.
    Owned(AlignedBuf),
}

/// The most a library read from a stream (a pipe, a device) may declare: 4 GiB, a thousand
/// times the largest preset table.
pub const MAX_STREAM_BYTES: u64 = 1 << 32;

impl Backing {
    pub fn bytes(&self) -> &[u8] {
        match self {
            Backing::Mapped(map) => map,
            Backing::Owned(buf) => buf.bytes(),
        }
    }

    /// Maps the file at `path` read-only (reads it, under Miri).
    #[allow(unsafe_code)]
    pub fn map(path: &Path) -> FormatResult<Backing> {
        if cfg!(miri) {
            // Miri cannot run the mmap system call; the code after a map only ever sees
            // `&[u8]`, which an owned buffer gives alike (docs/reliability.md)
            return Backing::read(path);
        }
        let file = File::open(path).map_err(|e| FormatError::io("open", path, e))?;
        let meta = file
            .metadata()
            .map_err(|e| FormatError::io("stat", path, e))?;
        if !meta.is_file() || meta.len() < super::spec::HEADER_SIZE as u64 {
            // Not a regular file (a folder, a pipe, a device) or too short to be a library:
            // a plain read gives its own error ("Is a directory") or reads the stream, where
            // a map would fail with ENODEV (mapping an empty file is an error on some systems).
            return Backing::read_file(file, path);
        }
        // SAFETY: the map is read-only and private to this `Backing`; Rust code only ever sees
        // it as `&[u8]`. The bytes may change if another process writes the file, which the
        // format tolerates (every value read is validated or CRC-checked, never trusted for
        // memory safety), and a truncation by another process raises SIGBUS, which the module
        // documentation states. The crate itself never writes a file in place.
        let map =
            unsafe { memmap2::Mmap::map(&file) }.map_err(|e| FormatError::io("map", path, e))?;
        Ok(Backing::Mapped(map))
    }

    /// Reads the file at `path` into an aligned buffer.
    pub fn read(path: &Path) -> FormatResult<Backing> {
        let file = File::open(path).map_err(|e| FormatError::io("open", path, e))?;
        Backing::read_file(file, path)
    }

    fn read_file(mut file: File, path: &Path) -> FormatResult<Backing> {
        let meta = file
            .metadata()
            .map_err(|e| FormatError::io("stat", path, e))?;
        if !meta.is_file() {
            return Backing::read_stream(file, path);
        }
        let len = meta.len();
        let len = usize::try_from(len).map_err(|_| FormatError::InvalidInput {
            message: format!("file of {len} bytes does not fit in memory"),
        })?;
        let mut buf = AlignedBuf::zeroed(len);
        file.read_exact(buf.bytes_mut())
            .map_err(|e| FormatError::io("read", path, e))?;
        // A file that grew since `stat` keeps its extra bytes visible as trailing bytes.
        let mut probe = [0u8; 1];
        let grew = file
            .read(&mut probe)
            .map_err(|e| FormatError::io("read", path, e))?;
        if grew != 0 {
            let mut rest = probe[..grew].to_vec();
            file.read_to_end(&mut rest)
                .map_err(|e| FormatError::io("read", path, e))?;
            let mut all = buf.bytes().to_vec();
            all.extend_from_slice(&rest);
            buf = AlignedBuf::copy_from(&all);
        }
        Ok(Backing::Owned(buf))
    }

    /// [`Backing::read_file`] of a file with no size (a pipe, a device): the header first,
    /// then as many bytes as its `file_size` says and one more (so that trailing bytes show),
    /// never more: a stream that never ends (`/dev/zero`) is read only as far as its header
    /// allows. Where the header is short, has not the magic or declares more than
    /// [`MAX_STREAM_BYTES`], what was read is the file, which the parse rejects.
    fn read_stream(file: File, path: &Path) -> FormatResult<Backing> {
        let io = |e| FormatError::io("read", path, e);
        let mut bytes = Vec::new();
        let mut header = file.take(HEADER_SIZE as u64);
        header.read_to_end(&mut bytes).map_err(io)?;
        let mut file = header.into_inner();
        let declared = (bytes.len() == HEADER_SIZE && bytes.starts_with(&MAGIC))
            .then(|| bytes.get(24..32).and_then(|b| b.try_into().ok()))
            .flatten()
            .map(u64::from_le_bytes);
        if let Some(size) = declared.filter(|&size| size <= MAX_STREAM_BYTES) {
            let rest = size.saturating_sub(HEADER_SIZE as u64).saturating_add(1);
            (&mut file).take(rest).read_to_end(&mut bytes).map_err(io)?;
        }
        Ok(Backing::Owned(AlignedBuf::copy_from(&bytes)))
    }

    pub fn is_mapped(&self) -> bool {
        matches!(self, Backing::Mapped(_))
    }
}
