//! The size of text on the screen, without a window: how much bigger than at 720 pixels
//! high a line is drawn, and how wide the built-in font's lines are.

/// How much bigger than at 720 pixels high text is drawn in a window `screen_height` high:
/// it grows with the window, but not beyond half as big again.
pub fn scale(screen_height: f32) -> f32 {
    (screen_height / 720.0).clamp(1.0, 1.5)
}

/// The built-in font is monospaced: each character is this many pixels wide a pixel of
/// font size.
pub const ADVANCE: f32 = 0.4375;

/// The width in pixels of `text` drawn at `size` (as at 720 pixels high) in the built-in
/// font, in a window `screen_height` high (font sizes are whole pixels).
pub fn width(text: &str, size: f32, screen_height: f32) -> f32 {
    let px = (size * scale(screen_height)).floor();
    text.chars().count() as f32 * ADVANCE * px
}
