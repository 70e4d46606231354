//! `model.png`, the icon FMI 2.0 puts at the archive's root (FMPy's GUI and most tools show it):
//! the FMU's block symbol drawn from its model description, 256 × 256 pixels, no text (no font
//! to ship): a block, one arrow in on the left per input and one out on the right per output
//! (at most 12 each), and inside it a sketch of what the model does, a step response settling
//! to its set point for a controller (a `modelName` ending in `Controller`), a growing
//! vibration for the machine models. Drawn with plotters' bitmap backend: the same description
//! gives the same bytes.

use anyhow::{Context, Result};
use model_description::{Causality, ModelDescription};
use plotters::prelude::*;

/// Side of the icon [px].
pub const SIZE: u32 = 256;

/// The `model.png` bytes of the model `md`.
pub fn model_png(md: &ModelDescription) -> Result<Vec<u8>> {
    let dir = tempfile::tempdir().context("temporary directory for model.png")?;
    let path = dir.path().join("model.png");
    draw(md, &path).map_err(|e| anyhow::anyhow!("drawing model.png of {}: {e}", md.model_name))?;
    std::fs::read(&path).with_context(|| path.display().to_string())
}

fn count(md: &ModelDescription, c: Causality) -> usize {
    md.variables().iter().filter(|v| v.causality == c).count().min(12)
}

fn draw(md: &ModelDescription, path: &std::path::Path) -> Result<(), Box<dyn std::error::Error>> {
    let root = BitMapBackend::new(path, (SIZE, SIZE)).into_drawing_area();
    root.fill(&WHITE)?;
    let controller = md.model_name.ends_with("Controller");
    let fill = if controller { RGBColor(214, 230, 250) } else { RGBColor(252, 226, 200) };
    let (x0, y0, x1, y1) = (60, 36, 196, 220);
    root.draw(&Rectangle::new([(x0, y0), (x1, y1)], fill.filled()))?;
    root.draw(&Rectangle::new([(x0, y0), (x1, y1)], BLACK.stroke_width(3)))?;
    let arrows = |n: usize, from: i32, to: i32| -> Vec<[(i32, i32); 2]> {
        (0..n).map(|k| y0 + (y1 - y0) * (2 * k as i32 + 1) / (2 * n as i32)).map(|y| [(from, y), (to, y)]).collect()
    };
    for [a, b] in
        arrows(count(md, Causality::Input), 8, x0).into_iter().chain(arrows(count(md, Causality::Output), x1, 248))
    {
        root.draw(&PathElement::new(vec![a, b], BLACK.stroke_width(2)))?;
        let (x, y) = b;
        root.draw(&Polygon::new(vec![(x, y), (x - 9, y - 5), (x - 9, y + 5)], BLACK.filled()))?;
    }
    // the sketch inside the block, in a 100 × 120 box
    let (bx, by, bw, bh) = (78.0, 68.0, 100.0, 120.0);
    let curve: Vec<(i32, i32)> = (0..=100)
        .map(|i| {
            let t = f64::from(i) / 100.0;
            let v = if controller {
                1.0 - (-6.0 * t).exp() * (18.0 * t).cos()
            } else {
                (2.5 * t).exp() / (2.5f64).exp() * (40.0 * t).sin()
            };
            let y = if controller { by + bh * (1.0 - 0.75 * v) } else { by + bh * (0.5 - 0.45 * v) };
            ((bx + bw * t) as i32, y as i32)
        })
        .collect();
    let axis = if controller { by + bh } else { by + bh * 0.5 };
    root.draw(&PathElement::new(
        vec![(bx as i32, axis as i32), ((bx + bw) as i32, axis as i32)],
        BLACK.stroke_width(1),
    ))?;
    root.draw(&PathElement::new(curve, RGBColor(30, 60, 160).stroke_width(3)))?;
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_product_has_a_png_icon_and_the_same_model_gives_the_same_bytes() {
        for p in &crate::PRODUCTS {
            let md = (p.description)();
            let a = super::model_png(md).unwrap();
            assert!(a.starts_with(b"\x89PNG\r\n\x1a\n"), "{}", md.model_name);
            assert_eq!(a, super::model_png(md).unwrap(), "{}: not reproducible", md.model_name);
        }
    }
}
