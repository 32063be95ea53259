//! The texts of a string dataset, checked where HDF5 1.10 does not check
//! them. HDF5 keeps variable-length strings in its global heap: each stored
//! value is a reference (the text's length, the address of a heap
//! collection, the index of an object in it), and the library reads the
//! object trusting the collection's own table of objects. A damaged file
//! whose reference or table points elsewhere makes it read out of bounds: a
//! crash, not an error (HDF5 1.14 checks these). Before any string dataset is
//! read, its references and the collections they point into are checked here
//! against the file format's layout (global heap collection, version 1, with
//! the 8-byte addresses and lengths that vibroatlas's files use).
//!
//! Every build keeps the guard, the `static-hdf5` one with HDF5 2.2 too: a
//! collection whose first object claims 0 bytes makes Debian's HDF5 1.10.8,
//! h5py's HDF5 2.0.0 and the bundled 2.2.0 loop forever on opening the file
//! (measured 2026-11-28: `inspect` of such a file, the guard switched off, was
//! still running after 30 s), and the guard's one message is the same in
//! every build.

use std::collections::HashMap;
use std::fs::File;
use std::io::Read;
use std::os::unix::fs::FileExt;
use std::path::Path;

/// A collection's signature.
const SIGNATURE: &[u8; 4] = b"GCOL";
/// A collection's header: signature, version (1), 3 reserved bytes, its size.
const HEADER: u64 = 16;
/// An object's header: its index (2 bytes), reference count (2), 4 reserved
/// bytes, its size (8); its bytes follow, padded to a multiple of 8.
const OBJECT_HEADER: u64 = 16;
/// A stored reference: the text's length in bytes (4), its collection's
/// address (8), its object's index (4).
const REFERENCE: usize = 16;

/// Checks that every text of `ds` (a contiguous 1-D dataset of
/// variable-length strings) refers to an object of its own length in a sound
/// collection; `Err`: what is wrong, for the message that names the dataset.
/// A file held in memory (the core driver, [`crate::image`]) has no bytes
/// on disk to read and was written by this process: it is not checked.
pub(crate) fn check(ds: &hdf5::Dataset) -> Result<(), String> {
    let n = ds.size();
    if n == 0 || in_memory(ds) {
        return Ok(());
    }
    let offset = ds.offset().ok_or("its texts are not stored contiguously, as vibroatlas stores them")?;
    let file = File::open(ds.filename()).map_err(|e| e.to_string())?;
    let len = file.metadata().map_err(|e| e.to_string())?.len();
    let bytes = read_at(&file, len, offset, n.saturating_mul(REFERENCE) as u64)?;
    let mut collections: HashMap<u64, HashMap<u16, u64>> = HashMap::new();
    for r in bytes.chunks_exact(REFERENCE) {
        let size = u64::from(u32::from_le_bytes(r[0..4].try_into().expect("4 bytes")));
        let address = u64::from_le_bytes(r[4..12].try_into().expect("8 bytes"));
        let index = u32::from_le_bytes(r[12..16].try_into().expect("4 bytes"));
        if address == 0 && size == 0 {
            continue;
        }
        let objects = match collections.entry(address) {
            std::collections::hash_map::Entry::Occupied(e) => e.into_mut(),
            std::collections::hash_map::Entry::Vacant(e) => e.insert(collection(&file, len, address)?),
        };
        let object = u16::try_from(index).ok().filter(|&i| i > 0).and_then(|i| objects.get(&i));
        if object != Some(&size) {
            return Err(format!(
                "a text refers to object {index} of the heap collection at byte {address}, which does not hold its {size} bytes"
            ));
        }
    }
    Ok(())
}

/// Whether the file of `ds` is held in memory by the core driver.
fn in_memory(ds: &hdf5::Dataset) -> bool {
    ds.file()
        .and_then(|f| f.access_plist())
        .is_ok_and(|p| matches!(p.driver(), hdf5::plist::file_access::FileDriver::Core(_)))
}

/// The objects (index: size in bytes) of the collection at `address`, walked
/// as the library walks it, every object within the collection, and the
/// collection within the file of `len` bytes.
fn collection(file: &File, len: u64, address: u64) -> Result<HashMap<u16, u64>, String> {
    let bad = |what: &str| format!("the heap collection at byte {address} {what}");
    let head = read_at(file, len, address, HEADER).map_err(|_| bad("lies outside the file"))?;
    if &head[0..4] != SIGNATURE || head[4] != 1 {
        return Err(bad("is not one (no signature GCOL, version 1)"));
    }
    let size = u64::from_le_bytes(head[8..16].try_into().expect("8 bytes"));
    if size < HEADER {
        return Err(bad("is smaller than its header"));
    }
    let chunk = read_at(file, len, address, size).map_err(|_| bad("extends past the end of the file"))?;
    walk(&chunk)
        .map_err(|(index, object)| bad(&format!("has an object ({index}, {object} bytes) that does not fit in it")))
}

/// The objects (index: size in bytes) of a collection's bytes, walked as
/// HDF5 walks them: each object's header and its bytes, padded to a
/// multiple of 8 (object 0, the free space, counting its header), must lie
/// within the collection; what is left after the last object, too short for
/// a header, is free space. `Err`: the first object that does not fit
/// (index, size). HDF5 1.10 loops forever on an object of size 0 and reads
/// out of bounds past one that overruns.
fn walk(chunk: &[u8]) -> Result<HashMap<u16, u64>, (u16, u64)> {
    let size = chunk.len() as u64;
    let mut objects = HashMap::new();
    let mut p = HEADER;
    while p + OBJECT_HEADER <= size {
        let at = p as usize;
        let index = u16::from_le_bytes(chunk[at..at + 2].try_into().expect("2 bytes"));
        let object = u64::from_le_bytes(chunk[at + 8..at + 16].try_into().expect("8 bytes"));
        let need = match index {
            0 => Some(object),
            _ => object.checked_add(7).map(|s| OBJECT_HEADER + s / 8 * 8),
        };
        match need.filter(|&n| n >= OBJECT_HEADER && p.checked_add(n).is_some_and(|end| end <= size)) {
            Some(n) => {
                objects.insert(index, object);
                p += n;
            }
            None => return Err((index, object)),
        }
    }
    Ok(objects)
}

/// Refuses a file with a corrupt global heap collection before the library
/// reads any of it (its text attributes included): every collection in the
/// file (signature `GCOL`, version 1, 4096 bytes at least, within the file;
/// anything else with those four bytes is data) is walked as [`walk`] does,
/// reading the file in blocks of 8 MiB.
fn check_collections(path: &Path) -> Result<(), crate::StoreError> {
    let io = |e| crate::StoreError::io(path, e);
    let mut file = File::open(path).map_err(io)?;
    let len = file.metadata().map_err(io)?.len();
    let mut block = vec![0u8; 8 << 20];
    // Bytes of the block before that carry over (a signature across blocks).
    let mut kept = 0usize;
    let mut start = 0u64;
    loop {
        let n = file.read(&mut block[kept..]).map_err(io)?;
        if n == 0 {
            break;
        }
        let have = kept + n;
        for at in block[..have].windows(4).enumerate().filter(|(_, w)| w == SIGNATURE).map(|(i, _)| i) {
            let offset = start + at as u64;
            let mut head = [0u8; HEADER as usize];
            if file.read_at(&mut head, offset).map_err(io)? < head.len() || head[4] != 1 {
                continue;
            }
            let size = u64::from_le_bytes(head[8..16].try_into().expect("8 bytes"));
            if size < 4096 || size > len - offset {
                continue;
            }
            let mut heap = vec![0u8; size as usize];
            file.read_exact_at(&mut heap, offset).map_err(io)?;
            if let Err((index, object)) = walk(&heap) {
                let what = format!(
                    "the global heap at byte {offset} is corrupt (object {index} of {object} bytes does not fit in it): the file is damaged"
                );
                return Err(crate::StoreError::format(path, what));
            }
        }
        // Keep the last 3 bytes: a signature may begin there.
        let carry = have.min(3);
        block.copy_within(have - carry..have, 0);
        start += (have - carry) as u64;
        kept = carry;
    }
    Ok(())
}

/// `count` bytes of `file` (`len` bytes long) from `offset`.
fn read_at(file: &File, len: u64, offset: u64, count: u64) -> Result<Vec<u8>, String> {
    if offset.checked_add(count).is_none_or(|end| end > len) {
        return Err(format!("{count} bytes at byte {offset} lie past the end of the file ({len} bytes)"));
    }
    let mut bytes = vec![0u8; count as usize];
    file.read_exact_at(&mut bytes, offset).map_err(|e| e.to_string())?;
    Ok(bytes)
}

/// Opens the HDF5 file at `path` once its global heap collections are
/// checked ([`check_collections`]): every reader opens its files so.
pub(crate) fn open(path: &Path) -> Result<hdf5::File, crate::StoreError> {
    if !has_signature(path) {
        let what = "not an HDF5 file (an atlas is the HDF5 file that vibroatlas atlas writes)";
        return Err(crate::StoreError::format(path, what.to_string()));
    }
    check_collections(path)?;
    hdf5::File::open(path).map_err(|e| crate::StoreError::hdf5(path, e))
}

/// Whether `path` holds HDF5's signature where the format puts it: at byte
/// 0, or after a user block of 512, 1024, 2048, … bytes.
fn has_signature(path: &Path) -> bool {
    use std::io::{Read, Seek, SeekFrom};
    const HDF5: &[u8; 8] = b"\x89HDF\r\n\x1a\n";
    let Ok(mut f) = std::fs::File::open(path) else { return true };
    let len = f.metadata().map_or(0, |m| m.len());
    std::iter::once(0u64).chain((9..40).map(|k| 1u64 << k)).take_while(|&at| at + 8 <= len).any(|at| {
        let mut head = [0u8; 8];
        f.seek(SeekFrom::Start(at)).is_ok() && f.read_exact(&mut head).is_ok() && &head == HDF5
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file with one dataset of texts, its references' offset in the file,
    /// and the file's bytes.
    fn written(name: &str) -> (std::path::PathBuf, u64, Vec<u8>) {
        // Shared by tests running at once, its files named for them: one folder however often the tests run.
        let dir = std::env::temp_dir().join("vibroatlas-heap");
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        let texts = ["no period within the record".to_string(), "1-3-3".to_string(), String::new()];
        let f = crate::netcdf::create_file(&path).unwrap();
        let offset = crate::netcdf::texts(&f, "t", &texts).unwrap().offset().unwrap();
        drop(f);
        let bytes = std::fs::read(&path).unwrap();
        (path, offset, bytes)
    }

    fn checked(path: &std::path::Path) -> Result<(), String> {
        let f = hdf5::File::open(path).unwrap();
        check(&f.dataset("t").unwrap())
    }

    /// Intact texts pass, and their references are what the format says: the
    /// first text's length, then a collection (signature GCOL) at its address.
    #[test]
    fn intact_texts_pass() {
        let (path, offset, bytes) = written("intact.h5");
        checked(&path).unwrap();
        let at = offset as usize;
        assert_eq!(u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()), 27);
        let address = u64::from_le_bytes(bytes[at + 4..at + 12].try_into().unwrap()) as usize;
        assert_eq!(&bytes[address..address + 4], SIGNATURE);
    }

    /// A reference to an object the collection does not hold, a text longer
    /// than its object, a collection address elsewhere, and an object whose
    /// size overruns its collection are each refused (HDF5 1.10 reads out of
    /// bounds on the first two).
    #[test]
    fn damaged_references_and_collections_are_refused() {
        let (path, offset, bytes) = written("damaged.h5");
        let at = offset as usize;
        let address = u64::from_le_bytes(bytes[at + 4..at + 12].try_into().unwrap()) as usize;
        let cases: [(usize, &[u8], &str); 4] = [
            (at + 12, &[0x40, 0x1f], "does not hold"),
            (at, &[200], "does not hold"),
            (at + 4, &[0x08], "heap collection at byte"),
            // The first object's size, 8 bytes after its header's start.
            (address + 16 + 8, &[0xff, 0xff, 0xff], "does not fit"),
        ];
        for (k, (place, new, what)) in cases.iter().enumerate() {
            let mut b = bytes.clone();
            b[*place..*place + new.len()].copy_from_slice(new);
            let p = path.with_file_name(format!("damaged{k}.h5"));
            std::fs::write(&p, &b).unwrap();
            let e = checked(&p).unwrap_err();
            assert!(e.contains(what), "case {k}: {e}");
        }
    }
}
