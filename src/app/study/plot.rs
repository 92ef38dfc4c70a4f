//! `study.png`: error against run time on log-log axes, one curve per
//! solver family (linear solver x EIL on/off), drawn with the `image`
//! crate and the study's bitmap font.
//!
//! Each curve joins a family's runs in ladder order (loosest tolerance
//! first); a filled marker is a converged run, a hollow one a run that hit
//! its step cap. The axes span whole decades around the data, with a
//! labelled major tick per decade and minor ticks at 2..9. Runs with a zero
//! error or time have no place on log axes and are left out (the returned
//! [`PlotInfo`] counts them, and `study.md` lists every run anyway).

use super::font::{draw_text, put, text_height, text_width};
use crate::io::{write_atomic, IoError};
use image::{ImageFormat, Rgb, RgbImage};
use std::io::Cursor;
use std::path::Path;

/// One run on the plot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlotPoint {
    pub wall_s: f64,
    pub rms_radii: f64,
    pub converged: bool,
}

/// One solver family's runs, in ladder order.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub label: String,
    pub points: Vec<PlotPoint>,
}

/// The decades the axes span and what could not be drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlotInfo {
    /// `log10` of the x (wall seconds) axis ends.
    pub x_decades: (i32, i32),
    /// `log10` of the y (RMS in radii) axis ends.
    pub y_decades: (i32, i32),
    /// Runs left out for a non-positive error or time.
    pub skipped: usize,
}

const BG: [u8; 3] = [255, 255, 255];
const INK: [u8; 3] = [30, 30, 30];
const GRID: [u8; 3] = [225, 225, 225];
const PALETTE: [[u8; 3]; 6] = [
    [200, 40, 40],
    [40, 90, 200],
    [30, 150, 60],
    [220, 140, 20],
    [140, 60, 170],
    [20, 160, 170],
];
const MARGIN_LEFT: u32 = 70;
const MARGIN_RIGHT: u32 = 20;
const MARGIN_TOP: u32 = 34;
const MARGIN_BOTTOM: u32 = 50;
const FONT: u32 = 2;

/// Whole decades around the positive values (at least one decade).
fn decades(values: impl Iterator<Item = f64>) -> (i32, i32) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if !lo.is_finite() {
        return (-1, 0);
    }
    let (a, b) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    if a == b {
        (a, a + 1)
    } else {
        (a, b)
    }
}

/// Draws the plot (`width` x `height` pixels).
pub fn render(series: &[Series], width: u32, height: u32) -> (RgbImage, PlotInfo) {
    let mut img = RgbImage::from_pixel(width, height, Rgb(BG));
    let drawable = |p: &&PlotPoint| p.wall_s > 0.0 && p.rms_radii > 0.0 && p.wall_s.is_finite();
    let all = || series.iter().flat_map(|s| &s.points).filter(drawable);
    let info = PlotInfo {
        x_decades: decades(all().map(|p| p.wall_s)),
        y_decades: decades(all().map(|p| p.rms_radii)),
        skipped: series.iter().map(|s| s.points.len()).sum::<usize>() - all().count(),
    };
    let (x0, x1) = (i64::from(MARGIN_LEFT), i64::from(width.saturating_sub(MARGIN_RIGHT)));
    let (y0, y1) = (i64::from(MARGIN_TOP), i64::from(height.saturating_sub(MARGIN_BOTTOM)));
    let (xd, yd) = (info.x_decades, info.y_decades);
    let px = |v: f64| x0 as f64 + (v.log10() - xd.0 as f64) / (xd.1 - xd.0) as f64 * (x1 - x0) as f64;
    let py = |v: f64| y1 as f64 - (v.log10() - yd.0 as f64) / (yd.1 - yd.0) as f64 * (y1 - y0) as f64;

    // Grid and ticks: major per decade (labelled), minor at 2..9.
    for d in xd.0..=xd.1 {
        for m in 1..10 {
            let x = px(f64::from(m) * 10f64.powi(d)).round() as i64;
            if d == xd.1 && m > 1 {
                break;
            }
            let len = if m == 1 { 8 } else { 4 };
            if m == 1 {
                vline(&mut img, x, y0, y1, GRID);
                let label = format!("1E{d}");
                let w = i64::from(text_width(&label, FONT));
                draw_text(&mut img, x - w / 2, y1 + 12, &label, FONT, INK);
            }
            vline(&mut img, x, y1 - len, y1, INK);
        }
    }
    for d in yd.0..=yd.1 {
        for m in 1..10 {
            let y = py(f64::from(m) * 10f64.powi(d)).round() as i64;
            if d == yd.1 && m > 1 {
                break;
            }
            let len = if m == 1 { 8 } else { 4 };
            if m == 1 {
                hline(&mut img, x0, x1, y, GRID);
                let label = format!("1E{d}");
                let w = i64::from(text_width(&label, FONT));
                let h = i64::from(text_height(FONT));
                draw_text(&mut img, x0 - 8 - w, y - h / 2, &label, FONT, INK);
            }
            hline(&mut img, x0, x0 + len, y, INK);
        }
    }
    // Frame and titles.
    vline(&mut img, x0, y0, y1, INK);
    vline(&mut img, x1, y0, y1, INK);
    hline(&mut img, x0, x1, y0, INK);
    hline(&mut img, x0, x1, y1, INK);
    let xlabel = "WALL TIME (S)";
    let xw = i64::from(text_width(xlabel, FONT));
    draw_text(&mut img, (x0 + x1) / 2 - xw / 2, y1 + 32, xlabel, FONT, INK);
    draw_text(
        &mut img,
        8,
        10,
        "RMS ERROR (YARN RADII) AGAINST THE REFERENCE",
        FONT,
        INK,
    );

    // Curves, markers and the legend.
    for (k, s) in series.iter().enumerate() {
        let colour = PALETTE[k % PALETTE.len()];
        let pts: Vec<(i64, i64, bool)> = s
            .points
            .iter()
            .filter(drawable)
            .map(|p| (px(p.wall_s).round() as i64, py(p.rms_radii).round() as i64, p.converged))
            .collect();
        for w in pts.windows(2) {
            line(&mut img, (w[0].0, w[0].1), (w[1].0, w[1].1), colour);
        }
        for &(x, y, filled) in &pts {
            marker(&mut img, x, y, filled, colour);
        }
        let ly = y0 + 10 + k as i64 * 16;
        let lx = x1 - 10 - i64::from(text_width(&s.label, FONT)) - 24;
        line(&mut img, (lx, ly + 4), (lx + 16, ly + 4), colour);
        marker(&mut img, lx + 8, ly + 4, true, colour);
        draw_text(&mut img, lx + 24, ly, &s.label, FONT, INK);
    }
    (img, info)
}

/// Renders and writes the plot as PNG, atomically.
pub fn write_plot(path: &Path, series: &[Series], width: u32, height: u32) -> Result<PlotInfo, IoError> {
    let (img, info) = render(series, width, height);
    let mut bytes = Vec::new();
    img.write_to(&mut Cursor::new(&mut bytes), ImageFormat::Png)
        .map_err(|e| IoError::Write {
            path: path.to_path_buf(),
            source: std::io::Error::other(e),
        })?;
    write_atomic(path, |w| w.write_all(&bytes))?;
    Ok(info)
}

fn vline(img: &mut RgbImage, x: i64, ya: i64, yb: i64, c: [u8; 3]) {
    for y in ya.min(yb)..=ya.max(yb) {
        put(img, x, y, c);
    }
}

fn hline(img: &mut RgbImage, xa: i64, xb: i64, y: i64, c: [u8; 3]) {
    for x in xa.min(xb)..=xa.max(xb) {
        put(img, x, y, c);
    }
}

/// A two-pixel-wide line (Bresenham with a 2 x 2 pen).
fn line(img: &mut RgbImage, a: (i64, i64), b: (i64, i64), c: [u8; 3]) {
    let (dx, dy) = ((b.0 - a.0).abs(), -(b.1 - a.1).abs());
    let (sx, sy) = ((b.0 - a.0).signum(), (b.1 - a.1).signum());
    let (mut x, mut y, mut err) = (a.0, a.1, dx + dy);
    loop {
        for (ox, oy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            put(img, x + ox, y + oy, c);
        }
        if (x, y) == b {
            break;
        }
        let e2 = 2 * err;
        if e2 >= dy {
            err += dy;
            x += sx;
        }
        if e2 <= dx {
            err += dx;
            y += sy;
        }
    }
}

/// A 9 x 9 square marker, filled or outlined.
fn marker(img: &mut RgbImage, x: i64, y: i64, filled: bool, c: [u8; 3]) {
    for dy in -4..=4i64 {
        for dx in -4..=4i64 {
            let edge = dx.abs() >= 3 || dy.abs() >= 3;
            let colour = if filled || edge { c } else { BG };
            put(img, x + dx, y + dy, colour);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series() -> Vec<Series> {
        let pts = |scale: f64| {
            [(0.5, 3.0, true), (1.2, 0.4, true), (4.0, 0.02, false)]
                .map(|(t, e, converged)| PlotPoint {
                    wall_s: t * scale,
                    rms_radii: e,
                    converged,
                })
                .to_vec()
        };
        vec![
            Series {
                label: "cpu-direct eil".into(),
                points: pts(1.0),
            },
            Series {
                label: "cpu-cg no-eil".into(),
                points: pts(2.0),
            },
        ]
    }

    #[test]
    fn the_plot_is_a_png_of_the_requested_size() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("study.png");
        let info = write_plot(&path, &series(), 640, 420).unwrap();
        let img = image::open(&path).unwrap();
        assert_eq!((img.width(), img.height()), (640, 420));
        assert_eq!(info.x_decades, (-1, 1));
        assert_eq!(info.y_decades, (-2, 1));
        assert_eq!(info.skipped, 0);
        // Both curve colours made it onto the image.
        let rgb = img.to_rgb8();
        for colour in &PALETTE[..2] {
            assert!(rgb.pixels().any(|p| p.0 == *colour));
        }
    }

    #[test]
    fn zero_errors_are_left_out_not_drawn_at_infinity() {
        let mut s = series();
        s[0].points[0].rms_radii = 0.0;
        let (img, info) = render(&s, 300, 200);
        assert_eq!(info.skipped, 1);
        assert_eq!((img.width(), img.height()), (300, 200));
    }
}
