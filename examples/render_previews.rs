//! Regenerates the gallery: one PNG preview per shipped pattern, compiled
//! from `patterns/*.knit` and drawn from the starting geometry (no
//! relaxation), into `docs/previews/<file stem>.png`.
//!
//! `cargo run --release --no-default-features --example render_previews [OUT_DIR]`
//!
//! The images are committed, so their size matters: a fixed width keeps
//! every preview the same size in the gallery whatever the pattern's
//! gauge, and a PNG of a few hundred pixels shows each stitch clearly.

use anyhow::Context;
use knitsim::io::{write_png, PngOptions, PngScale};
use knitsim::topology::{compile, CompileOptions};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Preview width in pixels: about 30 px per stitch for the 16- to 21-stitch
/// shipped swatches, and under 300 KB per file.
const WIDTH_PX: u32 = 600;

fn main() -> anyhow::Result<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::env::args_os()
        .nth(1)
        .map_or_else(|| root.join("docs/previews"), PathBuf::from);
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let mut files: Vec<PathBuf> = std::fs::read_dir(root.join("patterns"))?
        .map(|e| e.map(|e| e.path()))
        .collect::<Result<_, _>>()?;
    files.retain(|p| p.extension().is_some_and(|e| e == "knit"));
    files.sort();
    let options = PngOptions {
        scale: PngScale::Width(WIDTH_PX),
        ..PngOptions::default()
    };
    for file in files {
        let stem = file.file_stem().and_then(|s| s.to_str()).context("file name")?;
        let parsed = knitsim::pattern::load(&file)?;
        let fabric = compile(&parsed.pattern, &CompileOptions::default())
            .with_context(|| format!("compiling {}", file.display()))?;
        let png = out.join(format!("{stem}.png"));
        let t0 = Instant::now();
        write_png(&fabric, &png, &options)?;
        let kb = std::fs::metadata(&png)?.len() as f64 / 1024.0;
        println!(
            "{stem:20} {:>4.0} ms  {kb:>5.0} KB  {}",
            t0.elapsed().as_secs_f64() * 1e3,
            png.display()
        );
    }
    Ok(())
}
