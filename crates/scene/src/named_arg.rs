//! The clap value parser of a [`Named`] enum (the command line's
//! `--sweep`, `--preset`, …; with the feature `clap`), so that a library
//! type declares its own flags with its one table of names.

use crate::Named;
use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use std::ffi::OsStr;
use std::marker::PhantomData;

/// The clap value parser of a library enum, read through its [`Named`] table
/// (the one spelling the files, Python and the explorer use too): `--help`
/// lists every name with its help line, and a name that is none of them gets
/// clap's own error, which lists the names and suggests the closest.
#[derive(Clone)]
pub struct NamedParser<T>(PhantomData<T>);

/// [`NamedParser`] of `T`, for `#[arg(value_parser = named_arg::<T>())]`.
pub fn named_arg<T: Named + Send + Sync>() -> NamedParser<T> {
    NamedParser(PhantomData)
}

impl<T: Named + Send + Sync> NamedParser<T> {
    fn values() -> impl Iterator<Item = PossibleValue> {
        T::ALL.iter().map(|v| PossibleValue::new(v.name()).help(v.help()))
    }
}

impl<T: Named + Clone + Send + Sync> TypedValueParser for NamedParser<T> {
    type Value = T;

    fn parse_ref(&self, cmd: &clap::Command, arg: Option<&clap::Arg>, value: &OsStr) -> Result<T, clap::Error> {
        if let Some(v) = value.to_str().and_then(T::parse) {
            return Ok(v);
        }
        // A name outside the table: clap's own message, by its own parser of the names.
        let exact = PossibleValuesParser::new(Self::values()).parse_ref(cmd, arg, value)?;
        T::parse(&exact).ok_or_else(|| clap::Error::new(clap::error::ErrorKind::InvalidValue).with_cmd(cmd))
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(Self::values()))
    }
}
