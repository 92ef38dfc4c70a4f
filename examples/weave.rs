//! Writes a plain weave (`topology::weave`) as a topology JSON that
//! `knitsim drape` reads: the tablecloth of `examples/scenes/tablecloth.json`.
//!
//! `cargo run --release --example weave -- OUT.json [WARPS WEFTS]`
//! (default 16 x 16 yarns, 5.6 mm apart, radius 2.25 mm).

use knitsim::io::save_json;
use knitsim::topology::weave::{plain_weave, WeaveOptions};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let out = args
        .first()
        .ok_or_else(|| anyhow::anyhow!("usage: weave OUT.json [WARPS WEFTS]"))?;
    let mut o = WeaveOptions::default();
    if let (Some(w), Some(h)) = (args.get(1), args.get(2)) {
        o.warps = w.parse()?;
        o.wefts = h.parse()?;
    }
    let f = plain_weave(&o)?;
    save_json(&f, std::path::Path::new(out))?;
    eprintln!("{}: {} yarns, {} crossings", out, f.yarns.len(), f.contacts.len());
    Ok(())
}
