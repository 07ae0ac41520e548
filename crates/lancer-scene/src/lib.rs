//! Scene formats.
