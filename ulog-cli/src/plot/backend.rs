//! A `plotters` backend wrapper that measures text with the built-in font, and draws it
//! too on bitmaps (an SVG keeps `<text>` elements, drawn by the viewer).

use plotters_backend::{
    text_anchor::{HPos, VPos},
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
};

use super::font::Glyphs;

/// `inner`, with text measured (and drawn, when `raster`) by `glyphs`.
pub struct WithFont<B> {
    inner: B,
    glyphs: &'static Glyphs,
    raster: bool,
}

impl<B: DrawingBackend> WithFont<B> {
    /// Wraps `inner`; `raster`: draw text as pixels (bitmaps) rather than pass it on.
    pub fn new(inner: B, glyphs: &'static Glyphs, raster: bool) -> WithFont<B> {
        WithFont {
            inner,
            glyphs,
            raster,
        }
    }
}

type Res<B> = Result<(), DrawingErrorKind<<B as DrawingBackend>::ErrorType>>;

impl<B: DrawingBackend> DrawingBackend for WithFont<B> {
    type ErrorType = B::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }

    fn ensure_prepared(&mut self) -> Res<B> {
        self.inner.ensure_prepared()
    }

    fn present(&mut self) -> Res<B> {
        self.inner.present()
    }

    fn draw_pixel(&mut self, point: BackendCoord, color: BackendColor) -> Res<B> {
        self.inner.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Res<B> {
        self.inner.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Res<B> {
        self.inner.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Res<B> {
        self.inner.draw_path(path, style)
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Res<B> {
        self.inner.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Res<B> {
        self.inner.fill_polygon(vert, style)
    }

    fn blit_bitmap(&mut self, pos: BackendCoord, size: (u32, u32), src: &[u8]) -> Res<B> {
        self.inner.blit_bitmap(pos, size, src)
    }

    fn estimate_text_size<S: BackendTextStyle>(
        &self,
        text: &str,
        style: &S,
    ) -> Result<(u32, u32), DrawingErrorKind<Self::ErrorType>> {
        Ok(self.glyphs.measure(text, style.size()))
    }

    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Res<B> {
        if !self.raster {
            // The SVG backend escapes markup, not what XML cannot hold (a logged
            // message's control characters).
            return self
                .inner
                .draw_text(&crate::markup::plain(text), style, pos);
        }
        let colour = style.color();
        if colour.alpha == 0.0 {
            return Ok(());
        }
        let (w, h) = self.glyphs.measure(text, style.size());
        let (w, h) = (w as i32, h as i32);
        let anchor = style.anchor();
        let dx = match anchor.h_pos {
            HPos::Left => 0,
            HPos::Center => -w / 2,
            HPos::Right => -w,
        };
        let dy = match anchor.v_pos {
            VPos::Top => 0,
            VPos::Center => -h / 2,
            VPos::Bottom => -h,
        };
        let turn = style.transform();
        let mut result = Ok(());
        let inner = &mut self.inner;
        self.glyphs.raster(text, style.size(), |(x, y, c)| {
            if result.is_err() || c <= 0.0 {
                return;
            }
            let (x, y) = turn.transform(x + dx, y + dy);
            let pixel = BackendColor {
                alpha: colour.alpha * f64::from(c.min(1.0)),
                rgb: colour.rgb,
            };
            result = inner.draw_pixel((pos.0 + x, pos.1 + y), pixel);
        });
        result
    }
}
