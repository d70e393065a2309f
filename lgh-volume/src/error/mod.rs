//! The errors of lgh-volume, one type per phase: [`ReadError`] for reading a volume (VDB files,
//! caches, Blender's config), [`RenderError`] for lighting and rendering it. Each says what
//! went wrong with the data to say so (the path, the grid, the setting and its value) and, where
//! another crate's error is the cause, that error as [`source`](std::error::Error::source). The
//! CLI turns them into one line of text; a library user can match on them.

mod read;
mod render;

pub use read::ReadError;
pub use render::RenderError;

/// `Ok(value)` if `ok`, else [`RenderError::InvalidSetting`]: the one shape of every range
/// check of a real-valued setting.
pub(crate) fn check_setting(
    ok: bool,
    name: &'static str,
    value: f32,
    rule: &'static str,
) -> Result<f32, RenderError> {
    if ok {
        Ok(value)
    } else {
        Err(RenderError::InvalidSetting { name, value, rule })
    }
}
