//! The bitmap every plot draws on: plotters' `BitMapBackend` with text laid out by this module.
//!
//! Why: plotters 0.3.7 draws `ab_glyph` text glyph by glyph with each glyph's bitmap flush with
//! the pen position truncated to whole pixels: the left side bearing (`px_bounds().min.x`) and
//! the sub-pixel part of the pen are dropped. Ubuntu Light's default digits are tabular besides
//! (every digit as wide as a "0"), so the narrow "1" stands in a wide advance; with its bearing
//! moved to its right that gives the gaps of "1 33.3 Hz" and "1 st" (at 14 px the ink after a
//! "1" starts 4 px on, 2 px after any other digit). [`Canvas`] passes every drawing call to
//! the bitmap backend except text, which it lays out itself: proportional figures (the font's
//! own `pnum` alternates, found by their outlines), kerning, each glyph rasterised at its exact
//! pen position with its bearings, the baseline centring the digits in plotters' text box (the
//! box keeps plotters' height, so layouts that plotters computes from the font still fit).

use ab_glyph::{Font, FontRef, GlyphId, PxScale, ScaleFont, point};
use plotters::prelude::*;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind};
use std::path::Path;
use std::sync::OnceLock;

/// The font every plot uses (the TrueType bytes `epaint_default_fonts` ships: no system fonts).
fn font() -> &'static FontRef<'static> {
    static FONT: OnceLock<FontRef<'static>> = OnceLock::new();
    FONT.get_or_init(|| {
        FontRef::try_from_slice(epaint_default_fonts::UBUNTU_LIGHT).expect("the shipped font is a valid TrueType font")
    })
}

/// A PNG file being drawn: plotters' bitmap backend with correctly placed text.
pub struct Canvas<'a> {
    bitmap: BitMapBackend<'a>,
}

/// A drawing area on a [`Canvas`].
pub type Area<'a> = DrawingArea<Canvas<'a>, plotters::coord::Shift>;

/// A white canvas of `size` pixels that is written to `path` as PNG when presented.
pub fn canvas(path: &Path, size: (u32, u32)) -> Result<Area<'_>, super::DrawError> {
    super::register_font();
    let area = Canvas { bitmap: BitMapBackend::new(path, size) }.into_drawing_area();
    area.fill(&WHITE)?;
    Ok(area)
}

/// The font's proportional figures for '0'…'9' (the `pnum` alternates of Ubuntu's tabular
/// digits): for each digit, the narrowest other glyph with the same outline (shifted), if any.
fn proportional_digits() -> &'static [Option<GlyphId>; 10] {
    static DIGITS: OnceLock<[Option<GlyphId>; 10]> = OnceLock::new();
    DIGITS.get_or_init(|| {
        let f = font();
        let outlines: Vec<Option<ab_glyph::Outline>> =
            (0..f.glyph_count()).map(|i| f.outline(GlyphId(i as u16))).collect();
        std::array::from_fn(|d| {
            let id = f.glyph_id(char::from(b'0' + d as u8));
            let digit = outlines.get(usize::from(id.0))?.as_ref()?;
            let candidates = outlines.iter().enumerate().filter(|(i, _)| *i != usize::from(id.0));
            let same = candidates
                .filter_map(|(i, o)| Some((GlyphId(i as u16), o.as_ref()?)))
                .filter(|(_, o)| same_shape(digit, o));
            same.map(|(g, _)| g)
                .filter(|g| f.h_advance_unscaled(*g) <= f.h_advance_unscaled(id))
                .min_by(|a, b| f.h_advance_unscaled(*a).total_cmp(&f.h_advance_unscaled(*b)))
        })
    })
}

/// Are two outlines the same curves up to a horizontal shift (within half a font unit)?
fn same_shape(a: &ab_glyph::Outline, b: &ab_glyph::Outline) -> bool {
    use ab_glyph::OutlineCurve::{Cubic, Line, Quad};
    let dx = b.bounds.min.x - a.bounds.min.x;
    let near = |p: &ab_glyph::Point, q: &ab_glyph::Point| (p.x + dx - q.x).abs() < 0.5 && (p.y - q.y).abs() < 0.5;
    a.curves.len() == b.curves.len()
        && (a.bounds.max.y - b.bounds.max.y).abs() < 0.5
        && a.curves.iter().zip(&b.curves).all(|pair| match pair {
            (Line(p0, p1), Line(q0, q1)) => near(p0, q0) && near(p1, q1),
            (Quad(p0, p1, p2), Quad(q0, q1, q2)) => near(p0, q0) && near(p1, q1) && near(p2, q2),
            (Cubic(p0, p1, p2, p3), Cubic(q0, q1, q2, q3)) => {
                near(p0, q0) && near(p1, q1) && near(p2, q2) && near(p3, q3)
            }
            _ => false,
        })
}

/// The glyph drawn for `c`: the proportional figure for a digit.
fn glyph_of(c: char) -> GlyphId {
    match c.to_digit(10) {
        Some(d) => proportional_digits()[d as usize].unwrap_or_else(|| font().glyph_id(c)),
        None => font().glyph_id(c),
    }
}

/// One glyph of a laid-out line: its id and pen position.
struct Placed {
    id: GlyphId,
    x: f32,
}

/// The glyphs of `text` at `size` with their pen positions (advances and kerning), and the
/// line's advance width.
fn layout(text: &str, size: f32) -> (Vec<Placed>, f32) {
    let f = font().as_scaled(PxScale::from(size));
    let mut pen = 0.0f32;
    let mut prev = None;
    let mut out = Vec::with_capacity(text.len());
    for c in text.chars() {
        let id = glyph_of(c);
        if let Some(p) = prev {
            pen += f.kern(p, id);
        }
        out.push(Placed { id, x: pen });
        pen += f.h_advance(id);
        prev = Some(id);
    }
    (out, pen)
}

/// The text box of `text` at `size`: its advance width, and the height plotters' ab_glyph
/// layout gives a line (`size / 1.24`).
fn text_box(text: &str, size: f64) -> (i32, i32) {
    let (_, width) = layout(text, size as f32);
    (width as i32, (size / 1.24) as i32)
}

/// Every covered pixel of `text` at `size` in its box (x right, y down from the box's top left),
/// with its coverage in 0..1.
pub(crate) fn rasterize(text: &str, size: f64, mut pixel: impl FnMut(i32, i32, f32)) {
    let f = font().as_scaled(PxScale::from(size as f32));
    let (_, h) = text_box(text, size);
    // baseline: the digits' (cap) height centred in the box
    let zero = glyph_of('0').with_scale(PxScale::from(size as f32));
    let cap = f.outline_glyph(zero).map_or(f.ascent() * 0.7, |g| -g.px_bounds().min.y);
    let baseline = (h as f32 + cap) / 2.0;
    let (glyphs, _) = layout(text, size as f32);
    for g in glyphs {
        let glyph = g.id.with_scale_and_position(PxScale::from(size as f32), point(g.x, baseline));
        if let Some(o) = f.outline_glyph(glyph) {
            let b = o.px_bounds();
            o.draw(|x, y, c| pixel(b.min.x as i32 + x as i32, b.min.y as i32 + y as i32, c));
        }
    }
}

type Failed<'a> = DrawingErrorKind<<BitMapBackend<'a> as DrawingBackend>::ErrorType>;

impl<'a> DrawingBackend for Canvas<'a> {
    type ErrorType = <BitMapBackend<'a> as DrawingBackend>::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.bitmap.get_size()
    }
    fn ensure_prepared(&mut self) -> Result<(), Failed<'a>> {
        self.bitmap.ensure_prepared()
    }
    fn present(&mut self) -> Result<(), Failed<'a>> {
        self.bitmap.present()
    }
    fn draw_pixel(&mut self, point: BackendCoord, color: BackendColor) -> Result<(), Failed<'a>> {
        self.bitmap.draw_pixel(point, color)
    }
    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), Failed<'a>> {
        self.bitmap.draw_line(from, to, style)
    }
    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), Failed<'a>> {
        self.bitmap.draw_rect(upper_left, bottom_right, style, fill)
    }
    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), Failed<'a>> {
        self.bitmap.draw_path(path, style)
    }
    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), Failed<'a>> {
        self.bitmap.draw_circle(center, radius, style, fill)
    }
    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), Failed<'a>> {
        self.bitmap.fill_polygon(vert, style)
    }
    fn blit_bitmap(&mut self, pos: BackendCoord, size: (u32, u32), src: &[u8]) -> Result<(), Failed<'a>> {
        self.bitmap.blit_bitmap(pos, size, src)
    }

    fn estimate_text_size<T: BackendTextStyle>(&self, text: &str, style: &T) -> Result<(u32, u32), Failed<'a>> {
        let (w, h) = text_box(text, style.size());
        Ok((w.max(0) as u32, h.max(0) as u32))
    }

    /// As plotters' default (anchor, rotation, clipping), with the glyphs placed by [`rasterize`].
    fn draw_text<T: BackendTextStyle>(&mut self, text: &str, style: &T, pos: BackendCoord) -> Result<(), Failed<'a>> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let (width, height) = text_box(text, style.size());
        let dx = match style.anchor().h_pos {
            HPos::Left => 0,
            HPos::Right => -width,
            HPos::Center => -width / 2,
        };
        let dy = match style.anchor().v_pos {
            VPos::Top => 0,
            VPos::Center => -height / 2,
            VPos::Bottom => -height,
        };
        let trans = style.transform();
        let (w, h) = self.get_size();
        let mut result = Ok(());
        rasterize(text, style.size(), |x, y, coverage| {
            let (x, y) = trans.transform(x + dx, y + dy);
            let (x, y) = (pos.0 + x, pos.1 + y);
            if result.is_ok() && x >= 0 && x < w as i32 && y >= 0 && y < h as i32 {
                let c = BackendColor { alpha: color.alpha * f64::from(coverage), rgb: color.rgb };
                result = self.bitmap.draw_pixel((x, y), c);
            }
        });
        result
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Where the ink of "133.3 1st" is, as plotters draws it and as [`rasterize`] does.
    #[test]
    fn digits_are_proportional_and_placed_with_their_bearings() {
        crate::plot::register_font();
        let (size, text) = (14.0, "133.3 1st");
        // plotters 0.3.7: every glyph flush with its whole-pixel pen, tabular digits
        let style = TextStyle::from((super::super::FONT, size).into_font());
        let mut cols = std::collections::BTreeSet::new();
        let _ = BackendTextStyle::draw(&style, text, (0, 0), |x, _, c| {
            if c.alpha > 0.3 {
                cols.insert(x);
            }
            Ok::<(), ()>(())
        });
        let theirs = runs(cols);
        let gap = |r: &[(i32, i32)], i: usize| r[i + 1].0 - r[i].1 - 1;
        // the gap after the "1" of "133.3" is twice that between the threes (the bug)
        assert!(gap(&theirs, 0) >= 2 * gap(&theirs, 1), "plotters: {theirs:?}");
        // here: the "1" no wider apart than the other digits, and "1st" tight
        let ours = ink_runs(text, size);
        assert!(gap(&ours, 0) <= gap(&ours, 1), "ours: {ours:?}");
        let st = ours.len() - 3; // "1", "s", "t" are the last three runs
        assert!(gap(&ours, st) <= 1, "\"1st\": {ours:?}");
        // the proportional figures are the font's own (the same outline, a narrower advance)
        let f = font();
        let one = proportional_digits()[1].expect("Ubuntu has proportional figures");
        assert!(f.h_advance_unscaled(one) < f.h_advance_unscaled(f.glyph_id('1')));
        assert!(proportional_digits().iter().all(Option::is_some));
        // a glyph's ink starts at its left bearing ("[": 3.6 px at 40 px), not at the pen
        let f40 = f.as_scaled(PxScale::from(40.0));
        let lsb = f40.h_side_bearing(f.glyph_id('['));
        assert!((ink_runs("[", 40.0)[0].0 as f32 - lsb).abs() <= 1.0, "{:?} vs bearing {lsb}", ink_runs("[", 40.0));
        // the box is the advance width
        let (_, advance) = layout("11", 40.0);
        assert_eq!(text_box("11", 40.0).0, advance as i32);
    }

    fn runs(cols: std::collections::BTreeSet<i32>) -> Vec<(i32, i32)> {
        let mut runs: Vec<(i32, i32)> = Vec::new();
        for x in cols {
            match runs.last_mut() {
                Some(r) if r.1 + 1 == x => r.1 = x,
                _ => runs.push((x, x)),
            }
        }
        runs
    }

    /// The columns a text's pixels cover, as runs of inked columns.
    fn ink_runs(text: &str, size: f64) -> Vec<(i32, i32)> {
        let mut cols = std::collections::BTreeSet::new();
        rasterize(text, size, |x, _, c| {
            if c > 0.3 {
                cols.insert(x);
            }
        });
        runs(cols)
    }
}
