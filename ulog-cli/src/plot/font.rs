//! The text font, built into the binary (a DejaVu Sans subset, see `assets/README.md`):
//! text metrics for the layout of every picture, and glyphs for bitmaps.
//!
//! `plotters` is used without any font feature of its own (its `ttf` feature would need
//! system fonts; its `ab_glyph` feature would change the fonts of every other user of
//! `plotters` built alongside, such as criterion's reports), so text goes through
//! [`super::backend::WithFont`] and this module.

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};

static DATA: &[u8] = include_bytes!("../../assets/DejaVuSans-subset.ttf");

/// The built-in font.
pub struct Glyphs {
    font: FontRef<'static>,
}

/// A glyph's coverage of one pixel, in text coordinates: x to the right of the text's
/// left edge, y down from its top (the top of the line box).
pub type Coverage = (i32, i32, f32);

impl Glyphs {
    /// The built-in font, loaded once; `None` if it does not load (it is checked by the
    /// tests, so this does not happen in a released binary).
    pub fn get() -> Option<&'static Glyphs> {
        static GLYPHS: OnceLock<Option<Glyphs>> = OnceLock::new();
        GLYPHS
            .get_or_init(|| {
                FontRef::try_from_slice(DATA)
                    .ok()
                    .map(|font| Glyphs { font })
            })
            .as_ref()
    }

    /// The scale of text whose `plotters` size is `size`: `plotters` sizes are 1.24 times
    /// the em size (the SVG backend writes `font-size` as `size / 1.24`), and ab_glyph
    /// scales by the line height (ascent − descent).
    fn scale(&self, size: f64) -> PxScale {
        let em = (size / 1.24) as f32;
        let upem = self.font.units_per_em().unwrap_or(2048.0);
        PxScale::from(em * self.font.height_unscaled() / upem)
    }

    /// Width and height (one line) in pixels of `text` at `size`.
    pub fn measure(&self, text: &str, size: f64) -> (u32, u32) {
        let f = self.font.as_scaled(self.scale(size));
        let mut width = 0.0f32;
        let mut prev = None;
        for c in text.chars() {
            let id = f.glyph_id(c);
            if let Some(p) = prev {
                width += f.kern(p, id);
            }
            width += f.h_advance(id);
            prev = Some(id);
        }
        (width.ceil().max(0.0) as u32, f.height().ceil() as u32)
    }

    /// Calls `pixel` for every pixel `text` at `size` covers, in text coordinates.
    pub fn raster(&self, text: &str, size: f64, mut pixel: impl FnMut(Coverage)) {
        let f = self.font.as_scaled(self.scale(size));
        let mut caret = 0.0f32;
        let mut prev = None;
        for c in text.chars() {
            let id = f.glyph_id(c);
            if let Some(p) = prev {
                caret += f.kern(p, id);
            }
            let glyph = id.with_scale_and_position(f.scale(), ab_glyph::point(caret, f.ascent()));
            if let Some(outline) = f.outline_glyph(glyph) {
                let b = outline.px_bounds();
                let (x0, y0) = (b.min.x as i32, b.min.y as i32);
                outline.draw(|x, y, c| pixel((x0 + x as i32, y0 + y as i32, c)));
            }
            caret += f.h_advance(id);
            prev = Some(id);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Glyphs;

    #[test]
    fn the_built_in_font_loads_and_measures() {
        let g = Glyphs::get().expect("built-in font");
        let (w1, h) = g.measure("m", 20.0);
        let (w3, h3) = g.measure("mmm", 20.0);
        assert!(w1 > 5 && w1 < 20, "{w1}");
        assert!(w3 >= 3 * w1 - 2 && w3 <= 3 * w1 + 2);
        assert_eq!(h, h3);
        assert!(h > 14 && h < 26, "{h}");
        assert!(g.measure("m", 40.0).0 > w1, "grows with the size");
        assert_eq!(g.measure("", 20.0).0, 0);
    }

    #[test]
    fn glyphs_cover_pixels_inside_their_box() {
        let g = Glyphs::get().unwrap();
        let (w, h) = g.measure("Hx°", 24.0);
        let mut n = 0;
        g.raster("Hx°", 24.0, |(x, y, c)| {
            if c > 0.5 {
                n += 1;
                assert!(
                    x >= -1 && x <= w as i32 + 1 && y >= 0 && y <= h as i32,
                    "{x},{y}"
                );
            }
        });
        assert!(n > 50, "{n} pixels drawn");
    }
}
