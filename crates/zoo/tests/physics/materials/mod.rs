//! The named-material library: built-in media, files, errors and suggestions.

mod errors;
mod library;
