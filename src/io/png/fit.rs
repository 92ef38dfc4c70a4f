//! Picking a resolution that fits: the default preview draws 20 pixels per
//! millimetre, so a long strip (a 1000 x 2 stitch swatch is over 4 m) would
//! exceed the image size limit and the whole run's outputs would fail at
//! the picture. [`fit_preview`] lowers the resolution just enough instead.

use super::{PngOptions, PngScale};
use crate::topology::Fabric;

/// Share of `max_side_px` the estimate may use: the drawn tubes are
/// smoothed, so the picture can reach a little past the node box.
const SAFETY: f64 = 0.9;

/// `options` with its `PixelsPerMm` lowered, where needed, so the image of
/// `fabric` (its nodes' box in x and y, plus the thickest yarn's radius on
/// every side) stays within `max_side_px`. Other scales, fabrics without
/// finite nodes and pictures that fit are left as they are.
pub fn fit_preview(fabric: &Fabric, options: PngOptions) -> PngOptions {
    let PngScale::PixelsPerMm(ppm) = options.scale else {
        return options;
    };
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for n in &fabric.nodes {
        for k in 0..2 {
            lo[k] = lo[k].min(n.x[k]);
            hi[k] = hi[k].max(n.x[k]);
        }
    }
    let radius = fabric.meta.yarns.iter().map(|y| y.radius).fold(0.0, f64::max);
    let extent_mm = (0..2).map(|k| hi[k] - lo[k]).fold(0.0, f64::max) * 1e3 + 2e3 * radius;
    let room = SAFETY * f64::from(options.max_side_px) - 2.0 * f64::from(options.margin_px);
    if !(extent_mm.is_finite() && extent_mm > 0.0 && room > 0.0) || extent_mm * ppm <= room {
        return options;
    }
    PngOptions {
        scale: PngScale::PixelsPerMm(room / extent_mm),
        ..options
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::fixtures::{meta, push_yarn};
    use crate::topology::Vec3;

    #[test]
    fn a_long_strip_is_drawn_smaller_and_a_small_fabric_as_asked() {
        let mut f = Fabric {
            meta: meta(&[([0, 0, 0], 0.5e-3)]),
            nodes: vec![],
            yarns: vec![],
            contacts: vec![],
            sim: None,
        };
        push_yarn(&mut f, 0, &[Vec3::zeros(), Vec3::new(0.01, 0.0, 0.0)]);
        assert_eq!(fit_preview(&f, PngOptions::default()), PngOptions::default());
        f.nodes[1].x.x = 4.0;
        let fitted = fit_preview(&f, PngOptions::default());
        let PngScale::PixelsPerMm(ppm) = fitted.scale else {
            panic!("scale kind changed")
        };
        assert!(ppm < 2.0 && 4001.0 * ppm < 8192.0, "{ppm}");
        let image = crate::io::render_preview(&f, &fitted).expect("the fitted picture renders");
        assert!(image.width() <= 8192);
    }
}
