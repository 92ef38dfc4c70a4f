//! Every WGSL kernel under `shaders/` must parse and validate with naga, the
//! same front end wgpu uses, so shader errors show up in `cargo test` on
//! machines without any GPU adapter.

use std::path::{Path, PathBuf};

/// The host code dispatches `ceil(n / 256)` workgroups for the vector
/// kernels and one invocation for the scalar CG step; any other size would
/// silently skip or duplicate work.
const ALLOWED_WORKGROUP_SIZES: [[u32; 3]; 2] = [[256, 1, 1], [1, 1, 1]];

fn shader_files() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
        .map(|entry| entry.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "wgsl"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_shader_parses_and_validates() {
    let files = shader_files();
    assert!(!files.is_empty(), "no .wgsl files under shaders/");
    for path in files {
        let name = path.display().to_string();
        let source = std::fs::read_to_string(&path).expect("read shader");
        let module = naga::front::wgsl::parse_str(&source)
            .unwrap_or_else(|e| panic!("{}", e.emit_to_string_with_path(&source, &name)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string_with_path(&source, &name)));
        assert!(!module.entry_points.is_empty(), "{name}: no entry point");
        for ep in &module.entry_points {
            assert_eq!(
                ep.stage,
                naga::ShaderStage::Compute,
                "{name}: {} is not a compute entry",
                ep.name
            );
            assert!(
                ALLOWED_WORKGROUP_SIZES.contains(&ep.workgroup_size),
                "{name}: {} has workgroup size {:?}",
                ep.name,
                ep.workgroup_size
            );
        }
    }
}
