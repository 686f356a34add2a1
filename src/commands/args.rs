//! Arguments that name files: a map or experiment argument must be text (UTF-8), since its file
//! name becomes a name in tables and folders. clap's own refusal ("invalid UTF-8 was detected
//! in one or more arguments") named no argument; [`file_name`] is refused naming it.

use clap::builder::{OsStringValueParser, TypedValueParser};
use std::ffi::OsString;

/// A map or experiment name or path, as text; a value that is not UTF-8 is refused, naming the
/// argument (clap adds it) and shown with its bad bytes replaced.
pub fn file_name() -> impl TypedValueParser<Value = String> {
    OsStringValueParser::new().try_map(|v: OsString| {
        v.into_string().map_err(|v| {
            format!(
                "'{}' is not valid UTF-8: maps and experiments are named in tables and folders by their file names, \
                 which must be text; rename the file",
                v.to_string_lossy()
            )
        })
    })
}
