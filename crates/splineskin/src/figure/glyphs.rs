//! A 3 × 5 pixel font of digits, capital letters (lower case is drawn as capitals) and a few
//! signs (`- . % : = + / ( )`), for panel labels and colour-bar ticks: the renderer has no
//! font (usvg's `text` feature is off), and short labels and numbers are all it writes. Each
//! font pixel is drawn as a `scale × scale` square.

use resvg::tiny_skia::{Paint, Pixmap, Rect, Transform};

/// Width of a glyph in font pixels (the decimal point is 1 wide).
const GLYPH_WIDTH: u32 = 3;
/// Height of a glyph in font pixels.
pub const GLYPH_HEIGHT: u32 = 5;
/// Space between glyphs, in font pixels.
const GLYPH_SPACING: u32 = 1;

/// Rows of a glyph, top first, bit 2 the leftmost column (bit 0 for the one-column glyphs
/// `.` and `:`). Lower-case letters take the capitals' rows.
fn rows(c: char) -> Option<[u8; 5]> {
    Some(match c.to_ascii_uppercase() {
        '0' => [0b010, 0b101, 0b101, 0b101, 0b010],
        '1' => [0b010, 0b110, 0b010, 0b010, 0b111],
        '2' => [0b111, 0b001, 0b111, 0b100, 0b111],
        '3' => [0b111, 0b001, 0b011, 0b001, 0b111],
        '4' => [0b101, 0b101, 0b111, 0b001, 0b001],
        '5' => [0b111, 0b100, 0b111, 0b001, 0b111],
        '6' => [0b111, 0b100, 0b111, 0b101, 0b111],
        '7' => [0b111, 0b001, 0b010, 0b010, 0b010],
        '8' => [0b111, 0b101, 0b111, 0b101, 0b111],
        '9' => [0b111, 0b101, 0b111, 0b001, 0b111],
        '-' => [0b000, 0b000, 0b111, 0b000, 0b000],
        '.' => [0b0, 0b0, 0b0, 0b0, 0b1],
        ':' => [0b0, 0b1, 0b0, 0b1, 0b0],
        '%' => [0b101, 0b001, 0b010, 0b100, 0b101],
        '=' => [0b000, 0b111, 0b000, 0b111, 0b000],
        '+' => [0b000, 0b010, 0b111, 0b010, 0b000],
        '/' => [0b001, 0b001, 0b010, 0b100, 0b100],
        '(' => [0b010, 0b100, 0b100, 0b100, 0b010],
        ')' => [0b010, 0b001, 0b001, 0b001, 0b010],
        'A' => [0b010, 0b101, 0b111, 0b101, 0b101],
        'B' => [0b110, 0b101, 0b110, 0b101, 0b110],
        'C' => [0b011, 0b100, 0b100, 0b100, 0b011],
        'D' => [0b110, 0b101, 0b101, 0b101, 0b110],
        'E' => [0b111, 0b100, 0b110, 0b100, 0b111],
        'F' => [0b111, 0b100, 0b110, 0b100, 0b100],
        'G' => [0b011, 0b100, 0b101, 0b101, 0b011],
        'H' => [0b101, 0b101, 0b111, 0b101, 0b101],
        'I' => [0b111, 0b010, 0b010, 0b010, 0b111],
        'J' => [0b001, 0b001, 0b001, 0b101, 0b010],
        'K' => [0b101, 0b101, 0b110, 0b101, 0b101],
        'L' => [0b100, 0b100, 0b100, 0b100, 0b111],
        'M' => [0b101, 0b111, 0b111, 0b101, 0b101],
        'N' => [0b110, 0b101, 0b101, 0b101, 0b101],
        'O' => [0b111, 0b101, 0b101, 0b101, 0b111],
        'P' => [0b110, 0b101, 0b110, 0b100, 0b100],
        'Q' => [0b010, 0b101, 0b101, 0b110, 0b011],
        'R' => [0b110, 0b101, 0b110, 0b101, 0b101],
        'S' => [0b011, 0b100, 0b010, 0b001, 0b110],
        'T' => [0b111, 0b010, 0b010, 0b010, 0b010],
        'U' => [0b101, 0b101, 0b101, 0b101, 0b111],
        'V' => [0b101, 0b101, 0b101, 0b101, 0b010],
        'W' => [0b101, 0b101, 0b111, 0b111, 0b101],
        'X' => [0b101, 0b101, 0b010, 0b101, 0b101],
        'Y' => [0b101, 0b101, 0b010, 0b010, 0b010],
        'Z' => [0b111, 0b001, 0b010, 0b100, 0b111],
        _ => return None,
    })
}

/// Width of glyph `c` in font pixels.
fn glyph_width(c: char) -> u32 {
    if c == '.' || c == ':' {
        1
    } else {
        GLYPH_WIDTH
    }
}

/// Width of `text` in pixels at `scale` (characters the font lacks count as spaces).
pub fn text_width(text: &str, scale: u32) -> u32 {
    let n = text.chars().count() as u32;
    let glyphs: u32 = text.chars().map(glyph_width).sum();
    (glyphs + GLYPH_SPACING * n.saturating_sub(1)) * scale
}

/// Draws `text` with its top-left corner at pixel `(x, y)`, each font pixel a `scale × scale`
/// square of `paint`. Characters the font lacks are left blank.
pub fn draw_text(pixmap: &mut Pixmap, text: &str, x: f64, y: f64, scale: u32, paint: &Paint) {
    let s = f64::from(scale);
    let mut left = x;
    for c in text.chars() {
        let w = glyph_width(c);
        if let Some(rows) = rows(c) {
            for (r, bits) in rows.iter().enumerate() {
                for col in 0..w {
                    if (bits >> (w - 1 - col)) & 1 == 1 {
                        let px = left + f64::from(col) * s;
                        let py = y + r as f64 * s;
                        if let Some(rect) =
                            Rect::from_xywh(px as f32, py as f32, s as f32, s as f32)
                        {
                            pixmap.fill_rect(rect, paint, Transform::identity(), None);
                        }
                    }
                }
            }
        }
        left += f64::from(w + GLYPH_SPACING) * s;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn glyphs_every_glyph_is_distinct() {
        let all: Vec<[u8; 5]> = "0123456789-.%=+/()ABCDEFGHIJKLMNOPQRSTUVWXYZ"
            .chars()
            .map(|c| rows(c).unwrap())
            .collect();
        for i in 0..all.len() {
            for j in 0..i {
                assert_ne!(all[i], all[j], "glyphs {i} and {j}");
            }
        }
    }

    #[test]
    fn glyphs_draw_where_and_how_wide_they_say() {
        let mut pixmap = Pixmap::new(40, 20).unwrap();
        let mut paint = Paint::default();
        paint.set_color_rgba8(0, 0, 0, 255);
        paint.anti_alias = false;
        draw_text(&mut pixmap, "1.5", 2.0, 3.0, 2, &paint);
        assert_eq!(text_width("1.5", 2), (3 + 1 + 1 + 1 + 3) * 2);
        let inked = |x: u32, y: u32| pixmap.pixel(x, y).unwrap().alpha() == 255;
        // '1': top row is .X. → pixels x 4..6 at y 3..5.
        assert!(inked(4, 3) && !inked(2, 3));
        // '.': its one pixel at column 8 (after "1" and a space), bottom row (y 11..13).
        assert!(inked(10, 11) && !inked(10, 9));
        // '5': top row XXX from x 14.
        assert!(inked(14, 3) && inked(19, 3));
        // nothing right of the text
        assert!((0..20).all(|y| !inked(2 + text_width("1.5", 2), y)));
        // Lower case is drawn as capitals; unknown characters are blank, as wide as a digit.
        assert_eq!(rows('m'), rows('M'));
        assert_eq!(text_width("a b", 1), text_width("a9b", 1));
    }
}
