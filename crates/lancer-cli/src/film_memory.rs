//! How much memory a film takes, and the limit a render's film is held to (`--max-film-gib`).

use crate::cli_error::CliError;
use lancer::film::PixelBounds;

/// Memory a film over `bounds` needs: the accumulators and the finished image.
pub fn film_bytes(bounds: &PixelBounds) -> u64 {
    let per_pixel =
        std::mem::size_of::<lancer::film::PixelSum>() + std::mem::size_of::<lancer::math::Rgb>();
    bounds.area() * per_pixel as u64
}

/// Refuses a film over `bounds` bigger than `max_gib` GiB.
pub fn check_film_memory(bounds: &PixelBounds, max_gib: u64) -> Result<(), CliError> {
    if film_bytes(bounds) <= max_gib.saturating_mul(1 << 30) {
        return Ok(());
    }
    Err(CliError::input(format!(
        "a {}x{} image would need {:.1} GiB of memory for its film (the limit is {} GiB, \
         --max-film-gib to change it); render it in parts with --split or --crop",
        bounds.width(),
        bounds.height(),
        film_bytes(bounds) as f64 / (1u64 << 30) as f64,
        max_gib
    )))
}
