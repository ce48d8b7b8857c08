//! What the studies' plots share: the font their text is drawn in and a white canvas.

use std::path::Path;

use anyhow::anyhow;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;

/// The name the plots' text asks for; [`register_font`] makes it DejaVu Sans.
pub const FONT: &str = "sans-serif";

/// plotters draws text with ab_glyph, which needs a font registered by name; DejaVu Sans is
/// embedded in the binary by the `dejavu` crate, so no system font is needed.
pub fn register_font() -> anyhow::Result<()> {
    plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular())
        .map_err(|_| anyhow!("the embedded DejaVu Sans font is not a valid font"))
}

/// A white PNG of `size` pixels, written to `path` when it is presented.
pub fn canvas(
    path: &Path,
    size: (u32, u32),
) -> anyhow::Result<DrawingArea<BitMapBackend<'_>, Shift>> {
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
    Ok(root)
}
