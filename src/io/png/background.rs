//! Picking a background the yarns stand out against.
//!
//! One fixed backdrop cannot suit every pattern: an off-white yarn vanishes
//! on paper white, a navy one on charcoal, and two-colour work often has
//! one of each. We measure legibility with the WCAG 2 contrast ratio
//! `(L1 + 0.05) / (L2 + 0.05)` of relative luminances (`L = 0.2126 R +
//! 0.7152 G + 0.0722 B` in linear light), and take the first of a few
//! neutral backdrops, in order of preference, whose contrast with *every*
//! yarn reaches [`MIN_CONTRAST`]; when none does, the one whose worst
//! contrast is best. Neutral greys keep the yarn colours true.

/// Backdrops in order of preference: paper, mid grey, charcoal.
pub const BACKDROPS: [[u8; 3]; 3] = [[244, 242, 236], [128, 128, 128], [38, 38, 42]];

/// WCAG's threshold for large graphics (3:1); yarn tubes are large shapes
/// with dark outlines, so they need no more.
pub const MIN_CONTRAST: f64 = 3.0;

/// Relative luminance of an sRGB colour.
pub fn luminance(c: [u8; 3]) -> f64 {
    let [r, g, b] = c.map(super::srgb_to_linear);
    0.2126 * r + 0.7152 * g + 0.0722 * b
}

pub fn contrast_ratio(a: [u8; 3], b: [u8; 3]) -> f64 {
    let (la, lb) = (luminance(a), luminance(b));
    (la.max(lb) + 0.05) / (la.min(lb) + 0.05)
}

/// The backdrop for yarns of these colours (paper when there are none).
pub fn contrasting(yarns: &[[u8; 3]]) -> [u8; 3] {
    let worst = |bg: [u8; 3]| {
        yarns
            .iter()
            .map(|&y| contrast_ratio(bg, y))
            .fold(f64::INFINITY, f64::min)
    };
    if let Some(bg) = BACKDROPS.iter().find(|&&bg| worst(bg) >= MIN_CONTRAST) {
        return *bg;
    }
    BACKDROPS
        .iter()
        .copied()
        .max_by(|&a, &b| worst(a).total_cmp(&worst(b)))
        .unwrap_or(BACKDROPS[0])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wcag_reference_values() {
        // Black on white is 21:1 by definition; equal colours 1:1.
        assert!((contrast_ratio([0, 0, 0], [255, 255, 255]) - 21.0).abs() < 1e-9);
        assert!((contrast_ratio([90, 40, 10], [90, 40, 10]) - 1.0).abs() < 1e-12);
        // sRGB 128 grey: linear 0.2159, so against white (1.05) / 0.2659.
        let grey = contrast_ratio([128, 128, 128], [255, 255, 255]);
        assert!((grey - 1.05 / 0.265_9).abs() < 2e-3, "{grey}");
    }

    #[test]
    fn backdrop_suits_the_yarns() {
        // Luminances: navy 0.035, oatmeal 0.63, off-white 0.93; paper 0.89,
        // grey 0.216, charcoal 0.020.
        let navy = [29, 53, 87];
        let oatmeal = [217, 207, 193];
        let off_white = [241, 250, 238];
        assert_eq!(contrasting(&[navy]), BACKDROPS[0], "dark yarn on paper");
        // Oatmeal: 1.4 on paper, 2.6 on grey, 9.8 on charcoal.
        assert_eq!(contrasting(&[oatmeal]), BACKDROPS[2], "light yarn on charcoal");
        // Grey: 3.1 against navy, 3.7 against off-white.
        assert_eq!(contrasting(&[navy, off_white]), BACKDROPS[1], "both on grey");
        assert_eq!(contrasting(&[]), BACKDROPS[0]);
        for yarns in [vec![navy], vec![oatmeal], vec![navy, off_white]] {
            let bg = contrasting(&yarns);
            assert!(yarns.iter().all(|&y| contrast_ratio(bg, y) >= MIN_CONTRAST));
        }
    }
}
