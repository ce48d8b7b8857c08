//! `--screenshot`: the window's pixels as a PNG file.

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use anyhow::Context as _;
use macroquad::prelude::get_screen_data;

/// Saves what has been drawn this frame. Call after drawing and before `next_frame()`.
pub fn save_screen(path: &Path) -> anyhow::Result<()> {
    let image = get_screen_data();
    let (w, h) = (image.width as usize, image.height as usize);
    // The frame buffer's rows run bottom to top; a PNG's run top to bottom.
    let mut rows = Vec::with_capacity(w * h * 4);
    for y in (0..h).rev() {
        rows.extend_from_slice(&image.bytes[y * w * 4..(y + 1) * w * 4]);
    }
    let file = File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    let mut encoder = png::Encoder::new(BufWriter::new(file), w as u32, h as u32);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder
        .write_header()
        .with_context(|| format!("cannot write {}", path.display()))?;
    writer
        .write_image_data(&rows)
        .with_context(|| format!("cannot write {}", path.display()))?;
    writer
        .finish()
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}
