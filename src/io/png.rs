//! A shaded preview of the RS face as PNG, so a person sees the pattern at a
//! glance.
//!
//! The camera looks down the z axis from +z (the RS side; larger z is
//! nearer), orthographically, image up = +y. Each smoothed centre-line span
//! is drawn as a capsule of the yarn radius into a z-buffer
//! (the private `raster` module), so crossings show the yarn on top, and shaded
//! with its exact surface normal: Lambert with a little ambient, light from
//! the upper left front, and darkened towards silhouettes so that yarns of
//! one colour stay distinct where they cross. Shading and the supersampling average run in linear
//! light and are converted to sRGB at the end, so edges and highlights keep
//! the yarn's hue instead of darkening it.
//!
//! Output is deterministic: fixed draw order, strict depth test (the first
//! yarn drawn wins exact ties), no randomness, no threads.

use super::raster::{Canvas, Shading};
use super::smooth::{smooth_centre_line, SmoothOptions};
use super::validate::check_drawable;
use super::{write_atomic, ExportError, IoError};
use crate::topology::{Fabric, Vec3};
use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder, RgbImage};
use std::io;
use std::path::Path;

/// How big the image is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PngScale {
    /// Fixed resolution; the image size follows the fabric's extent.
    PixelsPerMm(f64),
    /// Fixed total width in pixels (margins included); height follows.
    Width(u32),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PngOptions {
    pub scale: PngScale,
    /// Empty border around the fabric's bounding box, in output pixels.
    pub margin_px: u32,
    /// sRGB.
    pub background: [u8; 3],
    /// Light reaching surfaces facing away from the light, in `[0, 1]`.
    pub ambient: f64,
    /// Direction towards the light (need not be unit): x right, y up, z
    /// towards the viewer.
    pub light: [f64; 3],
    /// Darkening towards yarn silhouettes in `[0, 1]` (0 = none).
    pub edge_darkening: f64,
    /// Rays per pixel along each axis (anti-aliasing); 1 disables it.
    pub supersample: u32,
    pub smooth: SmoothOptions,
    /// Refuse images larger than this on either side (memory guard).
    pub max_side_px: u32,
}

impl Default for PngOptions {
    fn default() -> Self {
        Self {
            scale: PngScale::PixelsPerMm(20.0),
            margin_px: 16,
            background: [244, 242, 236],
            ambient: 0.3,
            light: [-1.0, 1.0, 1.5],
            edge_darkening: 0.4,
            supersample: 3,
            smooth: SmoothOptions::default(),
            max_side_px: 8192,
        }
    }
}

/// Renders the preview and writes it as PNG (atomically).
pub fn write_png(fabric: &Fabric, path: &Path, options: &PngOptions) -> Result<(), IoError> {
    let image = render_preview(fabric, options).map_err(|source| IoError::Export {
        path: path.to_path_buf(),
        source,
    })?;
    write_atomic(path, |w| {
        PngEncoder::new(w)
            .write_image(image.as_raw(), image.width(), image.height(), ExtendedColorType::Rgb8)
            .map_err(io::Error::other)
    })
}

/// One smoothed yarn ready to draw.
struct DrawnYarn {
    samples: Vec<Vec3>,
    radius: f64,
    /// Linear RGB.
    color: [f64; 3],
}

/// Renders the preview in memory.
pub fn render_preview(fabric: &Fabric, options: &PngOptions) -> Result<RgbImage, ExportError> {
    check_drawable(fabric)?;
    let yarns: Vec<DrawnYarn> = fabric
        .curves()
        .iter()
        .map(|c| {
            let spec = &fabric.meta.yarns[c.spec];
            let points: Vec<Vec3> = c.points.iter().map(|p| p.x).collect();
            DrawnYarn {
                samples: smooth_centre_line(&points, spec.radius, &options.smooth),
                radius: spec.radius,
                color: spec.color.map(srgb_to_linear),
            }
        })
        .filter(|y| !y.samples.is_empty())
        .collect();
    let bounds = Bounds::of(&yarns).ok_or(ExportError::NothingToDraw)?;
    let layout = Layout::new(&bounds, options)?;

    let k = options.supersample.max(1) as usize;
    let margin_world = f64::from(options.margin_px) / layout.pixels_per_unit;
    let mut canvas = Canvas::new(
        layout.width as usize * k,
        layout.height as usize * k,
        bounds.min_x - margin_world,
        bounds.max_y + margin_world,
        layout.pixels_per_unit * k as f64,
        options.background.map(srgb_to_linear),
    );
    let light = Vec3::from(options.light).try_normalize(0.0).unwrap_or_else(Vec3::z);
    let shading = Shading {
        ambient: options.ambient.clamp(0.0, 1.0),
        light,
        edge: options.edge_darkening.clamp(0.0, 1.0),
    };
    for yarn in &yarns {
        let s = &yarn.samples;
        if s.len() == 1 {
            canvas.draw_capsule(s[0], s[0], yarn.radius, yarn.color, &shading);
        }
        for pair in s.windows(2) {
            canvas.draw_capsule(pair[0], pair[1], yarn.radius, yarn.color, &shading);
        }
    }
    Ok(downsample(&canvas, layout.width, layout.height, k))
}

/// Axis-aligned xy extent of all yarn surfaces.
struct Bounds {
    min_x: f64,
    max_x: f64,
    min_y: f64,
    max_y: f64,
}

impl Bounds {
    fn of(yarns: &[DrawnYarn]) -> Option<Self> {
        let mut b: Option<Bounds> = None;
        for y in yarns {
            for p in &y.samples {
                let r = y.radius;
                let e = b.get_or_insert(Bounds {
                    min_x: p.x - r,
                    max_x: p.x + r,
                    min_y: p.y - r,
                    max_y: p.y + r,
                });
                e.min_x = e.min_x.min(p.x - r);
                e.max_x = e.max_x.max(p.x + r);
                e.min_y = e.min_y.min(p.y - r);
                e.max_y = e.max_y.max(p.y + r);
            }
        }
        b
    }
}

/// Output image size and resolution.
struct Layout {
    width: u32,
    height: u32,
    /// Output pixels per world unit (metre).
    pixels_per_unit: f64,
}

impl Layout {
    fn new(b: &Bounds, options: &PngOptions) -> Result<Self, ExportError> {
        let (w, h) = (b.max_x - b.min_x, b.max_y - b.min_y);
        let margins = 2.0 * f64::from(options.margin_px);
        let pixels_per_unit = match options.scale {
            PngScale::PixelsPerMm(ppm) => ppm * 1e3,
            PngScale::Width(px) => (f64::from(px) - margins) / w,
        };
        if !(pixels_per_unit.is_finite() && pixels_per_unit > 0.0) {
            return Err(ExportError::BadScale(format!("{:?}", options.scale)));
        }
        // Round-off must not add a pixel column to an exact fit (5 mm at
        // 10 px/mm computes as 50.000000001).
        let cover = |extent: f64| (extent * pixels_per_unit * (1.0 - 1e-9)).ceil();
        let width = match options.scale {
            PngScale::Width(px) => f64::from(px),
            PngScale::PixelsPerMm(_) => cover(w) + margins,
        };
        let height = cover(h) + margins;
        let max = options.max_side_px;
        if width > f64::from(max) || height > f64::from(max) {
            return Err(ExportError::ImageTooLarge {
                width: width as u64,
                height: height as u64,
                max,
            });
        }
        Ok(Self {
            width: width.max(1.0) as u32,
            height: height.max(1.0) as u32,
            pixels_per_unit,
        })
    }
}

/// Box filter over `k x k` blocks, in linear light, then to sRGB bytes.
fn downsample(canvas: &Canvas, width: u32, height: u32, k: usize) -> RgbImage {
    let weight = 1.0 / (k * k) as f64;
    RgbImage::from_fn(width, height, |col, row| {
        let mut sum = [0.0; 3];
        for dy in 0..k {
            for dx in 0..k {
                let i = (row as usize * k + dy) * canvas.width + col as usize * k + dx;
                for (s, c) in sum.iter_mut().zip(canvas.color[i]) {
                    *s += c * weight;
                }
            }
        }
        image::Rgb(sum.map(linear_to_srgb))
    })
}

/// sRGB transfer function (IEC 61966-2-1).
fn srgb_to_linear(v: u8) -> f64 {
    let c = f64::from(v) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn linear_to_srgb(c: f64) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

#[cfg(test)]
mod tests;
