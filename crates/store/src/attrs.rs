//! Reading attributes: the one place they are read. Each is checked to be
//! of the type asked for before it is converted (an attribute of another
//! type is one error naming it, its object and both types), and the text
//! attributes of an object are checked against their checksum
//! ([`attr::ATTRIBUTES_CRC32`]) before any is used, as the texts of a
//! dataset against theirs ([`attr::TEXT_CRC32`]): HDF5 keeps texts in its
//! global heap, which has no checksum.

use crate::error::StoreError;
use crate::layout::attr;
use crate::netcdf;
use hdf5::types::{TypeDescriptor, VarLenUnicode};
use hdf5::{H5Type, Location};
use std::path::Path;

/// What a type holds, for messages (`a string`).
fn kind(d: &TypeDescriptor) -> &'static str {
    match d {
        TypeDescriptor::Integer(_) => "a signed integer",
        TypeDescriptor::Unsigned(_) => "an unsigned integer",
        TypeDescriptor::Float(_) => "a floating-point number",
        TypeDescriptor::Boolean => "a boolean",
        TypeDescriptor::Enum(_) => "an enumeration",
        TypeDescriptor::Compound(_) => "a compound value",
        TypeDescriptor::FixedArray(..) | TypeDescriptor::VarLenArray(_) => "an array",
        TypeDescriptor::FixedAscii(_) | TypeDescriptor::FixedUnicode(_) => "a fixed-length string",
        TypeDescriptor::VarLenAscii | TypeDescriptor::VarLenUnicode => "a string",
        TypeDescriptor::Reference(_) => "a reference",
    }
}

/// What a reader asking for `want` takes: its words, and whether `found` is
/// one of the types it converts from.
fn takes(want: &TypeDescriptor, found: &TypeDescriptor) -> (&'static str, bool) {
    use TypeDescriptor::{Float, Integer, Unsigned, VarLenUnicode};
    let integer = matches!(found, Integer(_) | Unsigned(_));
    match want {
        Unsigned(_) => ("an unsigned integer", integer),
        Integer(_) => ("an integer", integer),
        Float(_) => ("a number", integer || matches!(found, Float(_))),
        VarLenUnicode => ("a string", matches!(found, VarLenUnicode)),
        other => (kind(other), want == found),
    }
}

/// The name of `loc` in messages (`/`, `/axes/omega`).
fn object(loc: &Location) -> String {
    let name = loc.name();
    if name.is_empty() {
        "/".into()
    } else {
        name
    }
}

/// An error about attribute `name` of `loc`.
fn bad(path: &Path, loc: &Location, name: &str, message: impl std::fmt::Display) -> StoreError {
    StoreError::format(path, format!("attribute {name} of {}: {message}", object(loc)))
}

/// Attribute `name` of `loc`, checked to be of a type that converts to `T`
/// (and, with `scalar`, one value); `None` where there is none.
fn open<T: H5Type>(
    path: &Path,
    loc: &Location,
    name: &str,
    scalar: bool,
) -> Result<Option<hdf5::Attribute>, StoreError> {
    let h = |e: hdf5::Error| StoreError::hdf5(path, e);
    if !loc.attr_names().map_err(h)?.iter().any(|n| n == name) {
        return Ok(None);
    }
    let a = loc.attr(name).map_err(h)?;
    let found = a.dtype().and_then(|d| d.to_descriptor()).map_err(h)?;
    let (want, ok) = takes(&T::type_descriptor(), &found);
    if !ok {
        return Err(bad(path, loc, name, format!("expected {want}, found {}", kind(&found))));
    }
    if scalar && a.size() != 1 {
        return Err(bad(path, loc, name, format!("expected one value, found {}", a.size())));
    }
    if !scalar && a.ndim() > 1 {
        return Err(bad(path, loc, name, format!("expected a list of values, found shape {:?}", a.shape())));
    }
    Ok(Some(a))
}

/// The value of attribute `name` of `loc`, one value of a type that
/// converts to `T`; `None` where there is none.
pub(crate) fn optional<T: H5Type>(path: &Path, loc: &Location, name: &str) -> Result<Option<T>, StoreError> {
    let Some(a) = open::<T>(path, loc, name, true)? else { return Ok(None) };
    let v = if a.is_scalar() { a.read_scalar::<T>() } else { a.read_raw::<T>().map(|mut v| v.remove(0)) };
    v.map(Some).map_err(|e| StoreError::hdf5(path, e))
}

/// [`optional`], the attribute required.
pub(crate) fn required<T: H5Type>(path: &Path, loc: &Location, name: &str) -> Result<T, StoreError> {
    optional(path, loc, name)?.ok_or_else(|| bad(path, loc, name, "missing"))
}

/// The values of the 1-D attribute `name` of `loc`; `None` where there is none.
pub(crate) fn values<T: H5Type>(path: &Path, loc: &Location, name: &str) -> Result<Option<Vec<T>>, StoreError> {
    let Some(a) = open::<T>(path, loc, name, false)? else { return Ok(None) };
    a.read_raw::<T>().map(Some).map_err(|e| StoreError::hdf5(path, e))
}

/// The text attribute `name` of `loc` (UTF-8); `None` where there is none.
pub(crate) fn text(path: &Path, loc: &Location, name: &str) -> Result<Option<String>, StoreError> {
    optional::<VarLenUnicode>(path, loc, name)?
        .map(|v| String::from_utf8(v.as_bytes().to_vec()).map_err(|_| bad(path, loc, name, "a text that is not UTF-8")))
        .transpose()
}

/// [`text`], the attribute required.
pub(crate) fn required_text(path: &Path, loc: &Location, name: &str) -> Result<String, StoreError> {
    text(path, loc, name)?.ok_or_else(|| bad(path, loc, name, "missing"))
}

/// What a checksum attribute `name` that does not match says.
pub(crate) fn mismatch(name: &str) -> String {
    format!(
        "do not match their checksum (attribute {name}): the file is damaged or was changed since vibroatlas wrote it"
    )
}

/// Checks the text attributes of `loc` against their checksum
/// ([`attr::ATTRIBUTES_CRC32`]; objects written before it have none).
pub(crate) fn verify(path: &Path, loc: &Location) -> Result<(), StoreError> {
    let Some(want) = optional::<u32>(path, loc, attr::ATTRIBUTES_CRC32)? else { return Ok(()) };
    let mut texts = netcdf::text_attributes(loc).map_err(|e| StoreError::hdf5(path, e))?;
    // Files before layout 3 did not cover a shard's `shard`.
    let older = optional::<u64>(path, loc, attr::LAYOUT_VERSION)?.is_some_and(|v| v < 3);
    if older && netcdf::attributes_crc32(&texts) != want {
        texts.retain(|(name, _)| name != attr::SHARD);
    }
    if netcdf::attributes_crc32(&texts) != want {
        let what = format!("the text attributes of {} {}", object(loc), mismatch(attr::ATTRIBUTES_CRC32));
        return Err(StoreError::format(path, what));
    }
    // Its numeric attributes, where it was written with their checksum. One
    // that is not a number (a text) is left to the reader that takes it,
    // which names its type.
    if let Some(numbers) = text(path, loc, attr::NUMBERS_CRC32)? {
        if netcdf::numbers_crc32(loc).is_ok_and(|crc| crc != Some(numbers)) {
            let what = format!("the numeric attributes of {} {}", object(loc), mismatch(attr::NUMBERS_CRC32));
            return Err(StoreError::format(path, what));
        }
    }
    Ok(())
}
