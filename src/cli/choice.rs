//! The value parser of every option that names one of a fixed set (a [`ValueEnum`]): clap's
//! own, but a wrong name is reported as `--mode heat: expected compression, friction or
//! vectors`, naming the option and the value as written, like every other bad input.

use clap::builder::{EnumValueParser, PossibleValue, TypedValueParser};
use clap::error::{Error, ErrorKind};
use clap::{Arg, Command, ValueEnum};
use std::ffi::OsStr;
use std::marker::PhantomData;

/// Parses a `E` by its names (and aliases); see the module documentation.
#[derive(Clone, Debug)]
pub struct Choice<E>(PhantomData<E>);

impl<E> Choice<E> {
    pub fn new() -> Self {
        Self(PhantomData)
    }
}

impl<E: ValueEnum + Clone + Send + Sync + 'static> TypedValueParser for Choice<E> {
    type Value = E;

    fn parse_ref(&self, cmd: &Command, arg: Option<&Arg>, value: &OsStr) -> Result<E, Error> {
        EnumValueParser::<E>::new().parse_ref(cmd, arg, value).map_err(|_| {
            let option = match (arg.and_then(Arg::get_long), arg) {
                (Some(long), _) => format!("--{long}"),
                (None, Some(positional)) => positional.get_id().to_string(),
                (None, None) => "value".into(),
            };
            let names: Vec<String> = self.names().collect();
            let message = format!("{option} {}: expected {}\n", value.to_string_lossy(), one_of(&names));
            Error::raw(ErrorKind::InvalidValue, message).with_cmd(cmd)
        })
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(E::value_variants().iter().filter_map(E::to_possible_value)))
    }
}

impl<E: ValueEnum> Choice<E> {
    /// The names `--help` lists (not the hidden ones or the aliases).
    fn names(&self) -> impl Iterator<Item = String> {
        E::value_variants()
            .iter()
            .filter_map(|v| v.to_possible_value())
            .filter(|p| !p.is_hide_set())
            .map(|p| p.get_name().to_string())
    }
}

/// `a, b or c`.
fn one_of(names: &[String]) -> String {
    match names {
        [] => String::new(),
        [only] => only.clone(),
        [init @ .., last] => format!("{} or {last}", init.join(", ")),
    }
}

/// The name `value` is given by on the command line.
pub fn name<E: ValueEnum>(value: &E) -> String {
    value.to_possible_value().map(|p| p.get_name().to_string()).unwrap_or_default()
}
