//! netCDF-4 conventions on plain HDF5: dimension scales (the HL library's
//! H5DS API, as netCDF-4 itself writes them), coordinate variables, and CF
//! attributes, so that xarray (h5netcdf and netCDF4 engines), netCDF tools and
//! h5py read the files with named dimensions and coordinates.

use hdf5::types::VarLenUnicode;
use hdf5::{Dataset, Group, H5Type, Location};
use ndarray::Array1;
use std::ffi::{c_char, c_uint, CString};

extern "C" {
    fn H5DSset_scale(dsid: hdf5_sys::h5i::hid_t, dimname: *const c_char) -> hdf5_sys::h5::herr_t;
    fn H5DSattach_scale(did: hdf5_sys::h5i::hid_t, dsid: hdf5_sys::h5i::hid_t, idx: c_uint) -> hdf5_sys::h5::herr_t;
}

/// The NAME netCDF-4 gives a dimension that has no coordinate variable.
const DIM_ONLY: &str = "This is a netCDF dimension but not a netCDF variable.";

fn check(code: hdf5_sys::h5::herr_t, what: &str) -> hdf5::Result<()> {
    if code < 0 {
        Err(hdf5::Error::from(what))
    } else {
        Ok(())
    }
}

/// Makes `ds` a dimension scale named `name`.
pub fn set_scale(ds: &Dataset, name: &str) -> hdf5::Result<()> {
    let c = CString::new(name).map_err(|_| hdf5::Error::from("dimension name with NUL"))?;
    // SAFETY: a valid dataset id and a NUL-terminated name; the library lock is held.
    hdf5::sync::sync(|| check(unsafe { H5DSset_scale(ds.id(), c.as_ptr()) }, "H5DSset_scale failed"))
}

/// Attaches the dimension scale `scale` to dimension `idx` of `var`.
pub fn attach(var: &Dataset, scale: &Dataset, idx: usize) -> hdf5::Result<()> {
    // SAFETY: valid dataset ids; the library lock is held.
    hdf5::sync::sync(|| {
        check(unsafe { H5DSattach_scale(var.id(), scale.id(), idx as c_uint) }, "H5DSattach_scale failed")
    })
}

/// Attaches `scales` to the dimensions of `var`, in order.
pub fn dims(var: &Dataset, scales: &[&Dataset]) -> hdf5::Result<()> {
    for (i, s) in scales.iter().enumerate() {
        attach(var, s, i)?;
    }
    Ok(())
}

/// A text value for HDF5 (a NUL, which HDF5 strings cannot hold, becomes a space).
pub fn text(s: &str) -> VarLenUnicode {
    s.replace('\0', " ").parse().unwrap_or_default()
}

/// A scalar text attribute.
pub fn attr_str(loc: &Location, name: &str, value: &str) -> hdf5::Result<()> {
    loc.new_attr::<VarLenUnicode>().create(name)?.write_scalar(&text(value))
}

/// A scalar numeric attribute.
pub fn attr_num<T: H5Type + Copy>(loc: &Location, name: &str, value: T) -> hdf5::Result<()> {
    loc.new_attr::<T>().create(name)?.write_scalar(&value)
}

/// A 1-D numeric attribute (CF `flag_values`, `flag_masks`, `valid_range`).
pub fn attr_array<T: H5Type + Copy>(loc: &Location, name: &str, values: &[T]) -> hdf5::Result<()> {
    loc.new_attr::<T>().shape(values.len()).create(name)?.write(&Array1::from(values.to_vec()))
}

/// CF `long_name` and `units` of a variable.
pub fn describe(ds: &Dataset, long_name: &str, units: &str) -> hdf5::Result<()> {
    attr_str(ds, crate::layout::attr::LONG_NAME, long_name)?;
    attr_str(ds, crate::layout::attr::UNITS, units)
}

/// A numeric coordinate variable: a dimension scale named `name` holding `values`.
pub fn coordinate(g: &Group, name: &str, values: &[f64], long_name: &str) -> hdf5::Result<Dataset> {
    let ds = g.new_dataset_builder().with_data(&Array1::from(values.to_vec())).create(name)?;
    set_scale(&ds, name)?;
    describe(&ds, long_name, "1")?;
    Ok(ds)
}

/// A string coordinate variable: a dimension scale named `name` holding
/// `values`, with their checksum ([`texts`]).
pub fn labels(g: &Group, name: &str, values: &[String], long_name: &str) -> hdf5::Result<Dataset> {
    let ds = texts(g, name, values)?;
    set_scale(&ds, name)?;
    attr_str(&ds, "long_name", long_name)?;
    Ok(ds)
}

/// A 1-D dataset of texts, with the checksum of their stored bytes
/// (attribute [`TEXT_CRC32`](crate::layout::attr::TEXT_CRC32)): HDF5 keeps
/// the texts in its global heap, which carries no checksum.
pub fn texts(g: &Group, name: &str, values: &[String]) -> hdf5::Result<Dataset> {
    let data: Vec<VarLenUnicode> = values.iter().map(|s| text(s)).collect();
    let ds = g.new_dataset_builder().with_data(&Array1::from(data.clone())).create(name)?;
    attr_num(&ds, crate::layout::attr::TEXT_CRC32, texts_crc32(data.iter().map(|t| t.as_bytes())))?;
    Ok(ds)
}

/// The CRC-32 of texts: each its byte length (u64, little-endian), then its bytes.
pub fn texts_crc32<'a>(texts: impl IntoIterator<Item = &'a [u8]>) -> u32 {
    let mut crc = crc32fast::Hasher::new();
    for t in texts {
        crc.update(&(t.len() as u64).to_le_bytes());
        crc.update(t);
    }
    crc.finalize()
}

/// The scalar text attributes of `loc` that the checksum covers
/// ([`CHECKED_TEXTS`](crate::layout::attr::CHECKED_TEXTS)), by name in byte
/// order: name and stored bytes.
pub fn text_attributes(loc: &Location) -> hdf5::Result<Vec<(String, Vec<u8>)>> {
    let mut names = loc.attr_names()?;
    names.retain(|n| crate::layout::attr::CHECKED_TEXTS.contains(&n.as_str()));
    names.sort();
    let mut out = Vec::new();
    for name in names {
        let a = loc.attr(&name)?;
        if !a.is_scalar() || a.dtype()?.to_descriptor()? != hdf5::types::TypeDescriptor::VarLenUnicode {
            continue;
        }
        let value = a.read_scalar::<VarLenUnicode>()?;
        out.push((name, value.as_bytes().to_vec()));
    }
    Ok(out)
}

/// The CRC-32 of text attributes: each its name and its value, as [`texts_crc32`] takes texts.
pub fn attributes_crc32(attributes: &[(String, Vec<u8>)]) -> u32 {
    texts_crc32(attributes.iter().flat_map(|(n, v)| [n.as_bytes(), v.as_slice()]))
}

/// The CRC-32 of the numeric attributes of `loc` that
/// [`NUMBERS_CRC32`](crate::layout::attr::NUMBERS_CRC32) covers, as its 8
/// hexadecimal digits; `None` where `loc` has none of them.
pub fn numbers_crc32(loc: &Location) -> hdf5::Result<Option<String>> {
    let mut names = loc.attr_names()?;
    names.retain(|n| crate::layout::attr::CHECKED_NUMBERS.contains(&n.as_str()));
    if names.is_empty() {
        return Ok(None);
    }
    names.sort();
    let mut crc = crc32fast::Hasher::new();
    for name in names {
        let values = loc.attr(&name)?.read_raw::<f64>()?;
        crc.update(&(name.len() as u64).to_le_bytes());
        crc.update(name.as_bytes());
        crc.update(&(values.len() as u64).to_le_bytes());
        values.iter().for_each(|v| crc.update(&v.to_bits().to_le_bytes()));
    }
    Ok(Some(format!("{:08x}", crc.finalize())))
}

/// Writes (again) the checksums of the attributes of `loc`, once they are
/// all written: of its numeric ones ([`numbers_crc32`], a text attribute,
/// where it has any), then of its text ones (attribute
/// [`ATTRIBUTES_CRC32`](crate::layout::attr::ATTRIBUTES_CRC32)).
pub fn seal(loc: &Location) -> hdf5::Result<()> {
    if let Some(numbers) = numbers_crc32(loc)? {
        replace_str(loc, crate::layout::attr::NUMBERS_CRC32, &numbers)?;
    }
    let name = crate::layout::attr::ATTRIBUTES_CRC32;
    let crc = attributes_crc32(&text_attributes(loc)?);
    unlink_attr(loc, name)?;
    attr_num(loc, name, crc)
}

/// The text attribute `name` of `loc` written as `value`, replacing one there.
pub fn replace_str(loc: &Location, name: &str, value: &str) -> hdf5::Result<()> {
    unlink_attr(loc, name)?;
    attr_str(loc, name, value)
}

/// Deletes the attribute `name` of `loc`, where it has one.
fn unlink_attr(loc: &Location, name: &str) -> hdf5::Result<()> {
    if loc.attr_names()?.iter().any(|n| n == name) {
        loc.delete_attr(name)?;
    }
    Ok(())
}

/// The dataset `name` of `values` shaped `shape`, one chunk deflated and
/// checksummed (Fletcher-32), so that a damaged byte, or a chunk zeroed with
/// its checksum, is an error on read rather than other values (the small
/// files: curves, basins).
pub fn deflated<T: H5Type + Copy>(g: &Group, name: &str, values: Vec<T>, shape: &[usize]) -> hdf5::Result<Dataset> {
    let n = values.len();
    let array = ndarray::ArrayD::from_shape_vec(shape.to_vec(), values)
        .map_err(|e| hdf5::Error::from(e.to_string().as_str()))?;
    let b = g.new_dataset_builder().with_data(&array);
    match n {
        // HDF5 cannot chunk an empty dataset.
        0 => b.create(name),
        _ => b.chunk(shape.iter().map(|&s| s.max(1)).collect::<Vec<_>>()).deflate(1).fletcher32().create(name),
    }
}

/// A dimension of length `len` without a coordinate variable (netCDF-4 writes
/// such a dimension as an empty dataset with this NAME).
pub fn dimension(g: &Group, name: &str, len: usize) -> hdf5::Result<Dataset> {
    let ds = g.new_dataset::<f32>().shape(len).create(name)?;
    set_scale(&ds, &format!("{DIM_ONLY}{len:>10}"))?;
    Ok(ds)
}

/// Creates (truncates) an HDF5 file in the HDF5 1.10 format: its metadata,
/// the index of every dataset's chunks included, carries checksums, so that a
/// damaged index is an error on read rather than chunks read as never
/// written (fill values). Readers of HDF5 1.10 and later (h5py, netCDF-C,
/// xarray) read it.
pub(crate) fn create_file(path: &std::path::Path) -> hdf5::Result<hdf5::File> {
    hdf5::File::with_options().with_fapl(|p| p.libver_v110()).create(path)
}

/// The bytes of the file `f` as it would be on disk (flushed first): the
/// image of a file held in memory by the core driver.
pub(crate) fn file_image(f: &hdf5::File) -> hdf5::Result<Vec<u8>> {
    use hdf5_sys::h5f::H5Fget_file_image;
    f.flush()?;
    hdf5::sync::sync(|| {
        let failed = || hdf5::Error::from("H5Fget_file_image failed");
        // SAFETY: an open file; a null buffer asks for the size, then a buffer of that size.
        let size =
            usize::try_from(unsafe { H5Fget_file_image(f.id(), std::ptr::null_mut(), 0) }).map_err(|_| failed())?;
        let mut bytes = vec![0u8; size];
        let got = unsafe { H5Fget_file_image(f.id(), bytes.as_mut_ptr().cast(), size) };
        if usize::try_from(got).ok() != Some(size) {
            return Err(failed());
        }
        Ok(bytes)
    })
}
