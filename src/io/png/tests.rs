use super::*;
use crate::io::fixtures::{meta, push_yarn};
use crate::topology::Fabric;

const MM: f64 = 1e-3;

fn fabric_with(specs: &[([u8; 3], f64)]) -> Fabric {
    Fabric {
        meta: meta(specs),
        nodes: vec![],
        yarns: vec![],
        contacts: vec![],
        sim: None,
    }
}

/// One horizontal orange yarn from (0,0) to (4,0) mm, radius 0.5 mm.
fn horizontal_yarn() -> Fabric {
    let mut f = fabric_with(&[([220, 120, 40], 0.5 * MM)]);
    push_yarn(
        &mut f,
        0,
        &[
            Vec3::zeros(),
            Vec3::new(2.0 * MM, 0.0, 0.0),
            Vec3::new(4.0 * MM, 0.0, 0.0),
        ],
    );
    f
}

const PAPER: [u8; 3] = [244, 242, 236];

fn options(ppm: f64) -> PngOptions {
    PngOptions {
        scale: PngScale::PixelsPerMm(ppm),
        margin_px: 5,
        background: Background::Fixed(PAPER),
        ..PngOptions::default()
    }
}

/// Chromaticity in linear light: proportional colours compare equal.
fn chroma(c: [u8; 3]) -> [f64; 3] {
    let lin = c.map(srgb_to_linear);
    let sum: f64 = lin.iter().sum();
    lin.map(|v| v / sum)
}

#[test]
fn size_follows_the_bounding_box_plus_margins() {
    // Extent: x from -0.5 to 4.5 mm, y from -0.5 to 0.5 mm, at 10 px/mm.
    let img = render_preview(&horizontal_yarn(), &options(10.0)).unwrap();
    assert_eq!((img.width(), img.height()), (50 + 10, 10 + 10));
}

#[test]
fn fixed_width_is_honoured() {
    let opts = PngOptions {
        scale: PngScale::Width(200),
        margin_px: 10,
        ..PngOptions::default()
    };
    let img = render_preview(&horizontal_yarn(), &opts).unwrap();
    assert_eq!(img.width(), 200);
    // 180 px for 5 mm: 36 px/mm, 1 mm tall -> 36 px + margins.
    assert_eq!(img.height(), 36 + 20);
}

#[test]
fn yarn_pixels_have_the_yarn_colour_and_the_rest_is_background() {
    let opts = options(10.0);
    let img = render_preview(&horizontal_yarn(), &opts).unwrap();
    let yarn_colour = chroma([220, 120, 40]);
    // Yarn centre line is the image's middle row; x = 2 mm is column 5 + 25.
    let on_yarn = img.get_pixel(30, 10).0;
    for (a, b) in chroma(on_yarn).iter().zip(yarn_colour) {
        assert!((a - b).abs() < 0.02, "pixel {on_yarn:?} is not yarn coloured");
    }
    assert!(on_yarn != PAPER);
    // Margins and the corner are pure background.
    for (x, y) in [(0, 0), (59, 19), (30, 1), (30, 18), (1, 10)] {
        assert_eq!(img.get_pixel(x, y).0, PAPER, "at ({x}, {y})");
    }
}

#[test]
fn shading_is_brighter_towards_the_light() {
    // Light from the upper left: the upper flank of a horizontal yarn is
    // brighter than the lower one.
    let img = render_preview(&horizontal_yarn(), &options(20.0)).unwrap();
    let mid_col = img.width() / 2;
    let centre_row = img.height() / 2;
    let luminance = |p: [u8; 3]| p.iter().map(|&c| u32::from(c)).sum::<u32>();
    let upper = luminance(img.get_pixel(mid_col, centre_row - 6).0);
    let lower = luminance(img.get_pixel(mid_col, centre_row + 6).0);
    assert!(upper > lower, "upper {upper} lower {lower}");
}

/// A red yarn along x under a blue one along y, crossing at (2, 2) mm.
fn crossing_yarns() -> Fabric {
    let mut f = fabric_with(&[([200, 30, 30], 0.4 * MM), ([30, 60, 200], 0.4 * MM)]);
    push_yarn(
        &mut f,
        0,
        &[Vec3::new(0.0, 2.0 * MM, 0.0), Vec3::new(4.0 * MM, 2.0 * MM, 0.0)],
    );
    // The blue yarn passes over the red one (larger z is nearer the viewer).
    push_yarn(
        &mut f,
        1,
        &[
            Vec3::new(2.0 * MM, 0.0, 0.5 * MM),
            Vec3::new(2.0 * MM, 4.0 * MM, 0.5 * MM),
        ],
    );
    f
}

#[test]
fn upper_yarn_is_visible_at_a_crossing() {
    let f = crossing_yarns();
    let img = render_preview(&f, &options(10.0)).unwrap();
    // Crossing at (2, 2) mm; the box starts at -0.4 mm, margin 5 px.
    let (col, row) = (5 + 24, 5 + 24);
    let c = chroma(img.get_pixel(col, row).0);
    assert!(
        c[2] > c[0],
        "crossing should show blue, got {:?}",
        img.get_pixel(col, row).0
    );
}

#[test]
fn output_is_deterministic_and_png_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
    let f = horizontal_yarn();
    write_png(&f, &a, &options(10.0)).unwrap();
    write_png(&f, &b, &options(10.0)).unwrap();
    let bytes = std::fs::read(&a).unwrap();
    assert_eq!(bytes, std::fs::read(&b).unwrap());
    let decoded = image::load_from_memory(&bytes).unwrap().to_rgb8();
    assert_eq!(decoded, render_preview(&f, &options(10.0)).unwrap());
}

#[test]
fn the_thread_count_changes_no_pixel() {
    // Two crossing yarns of different colours over several tiles.
    let f = crossing_yarns();
    let one = render_on(&f, &options(40.0), 1).unwrap();
    assert!(one.width() as usize > 2 * TILE_PX && one.height() as usize > 2 * TILE_PX);
    for workers in [2, 3, 7] {
        assert_eq!(
            render_on(&f, &options(40.0), workers).unwrap(),
            one,
            "{workers} workers"
        );
    }
}

#[test]
fn bad_requests_are_errors() {
    let f = horizontal_yarn();
    assert!(matches!(
        render_preview(&f, &options(-1.0)),
        Err(ExportError::BadScale(_))
    ));
    assert!(matches!(
        render_preview(&f, &options(1e6)),
        Err(ExportError::ImageTooLarge { .. })
    ));
    let empty = fabric_with(&[([0, 0, 0], MM)]);
    assert_eq!(render_preview(&empty, &options(10.0)), Err(ExportError::NothingToDraw));
}

#[test]
fn tiles_leave_no_seams() {
    // A straight horizontal yarn is shaded the same all along its axis, so
    // every pixel of a row across its middle must be equal, including
    // across the tile boundaries at multiples of 32 columns.
    let img = render_preview(&horizontal_yarn(), &options(20.0)).unwrap();
    assert!(img.width() > 3 * 32);
    for row in [img.height() / 2 - 5, img.height() / 2, img.height() / 2 + 7] {
        let first = img.get_pixel(20, row);
        for col in 20..img.width() - 20 {
            assert_eq!(img.get_pixel(col, row), first, "row {row}, column {col}");
        }
    }
}

#[test]
fn deeper_yarn_fades_towards_the_background() {
    // Two parallel yarns of one colour, one 2 mm behind the other: with the
    // depth cue the back one is nearer the background colour.
    let mut f = fabric_with(&[([200, 30, 30], 0.4 * MM)]);
    push_yarn(&mut f, 0, &[Vec3::new(0.0, 0.0, 0.0), Vec3::new(4.0 * MM, 0.0, 0.0)]);
    push_yarn(
        &mut f,
        0,
        &[
            Vec3::new(0.0, 2.0 * MM, -2.0 * MM),
            Vec3::new(4.0 * MM, 2.0 * MM, -2.0 * MM),
        ],
    );
    let distance_to_paper = |p: [u8; 3]| -> i32 {
        p.iter()
            .zip(PAPER)
            .map(|(&a, b)| (i32::from(a) - i32::from(b)).abs())
            .sum()
    };
    let faded = render_preview(&f, &options(10.0)).unwrap();
    let flat = render_preview(
        &f,
        &PngOptions {
            depth_fade: 0.0,
            ..options(10.0)
        },
    )
    .unwrap();
    // Yarn centres: y = 0 mm at row 5 + 24, y = 2 mm at row 5 + 4.
    let (col, front_row, back_row) = (25, 29, 9);
    // The front yarn's crest is the nearest surface: (almost) no fade.
    let front_change =
        distance_to_paper(flat.get_pixel(col, front_row).0) - distance_to_paper(faded.get_pixel(col, front_row).0);
    assert!(front_change.abs() <= 6, "front changed by {front_change}");
    // The back crest is 2 of the 2.8 mm depth range deep: 36 % background.
    let (back_faded, back_flat) = (faded.get_pixel(col, back_row).0, flat.get_pixel(col, back_row).0);
    assert!(
        distance_to_paper(back_faded) * 4 < distance_to_paper(back_flat) * 3,
        "{back_faded:?} vs {back_flat:?}"
    );
    assert_eq!(
        flat.get_pixel(col, front_row),
        flat.get_pixel(col, back_row),
        "no cue: same shade"
    );
}
