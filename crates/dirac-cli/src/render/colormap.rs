//! The viridis colour map: perceptually uniform, monotone in lightness, readable in grey scale
//! and by viewers with the common colour-vision deficiencies; and the distinct colours of
//! segments ([`segment_colour`]).
//!
//! Source of the table: every fifth entry (indices 0, 5, …, 255) of `_viridis_data`, the
//! 256-entry sRGB table of matplotlib's viridis by Stéfan van der Walt, Nathaniel J. Smith and
//! Eric Firing (mpl-colormaps, released under CC0 1.0 / public domain). Linear interpolation
//! between these 52 samples reproduces the full table to within 0.7/255 per channel.

/// Sampled viridis, sRGB components in `[0, 1]`, at `t = i / 51`.
const VIRIDIS: [[f64; 3]; 52] = [
    [0.267004, 0.004874, 0.329415],
    [0.273809, 0.031497, 0.358853],
    [0.278791, 0.062145, 0.386592],
    [0.281924, 0.089666, 0.412415],
    [0.283197, 0.115680, 0.436115],
    [0.282623, 0.140926, 0.457517],
    [0.280255, 0.165693, 0.476498],
    [0.276194, 0.190074, 0.493001],
    [0.270595, 0.214069, 0.507052],
    [0.263663, 0.237631, 0.518762],
    [0.255645, 0.260703, 0.528312],
    [0.246811, 0.283237, 0.535941],
    [0.237441, 0.305202, 0.541921],
    [0.227802, 0.326594, 0.546532],
    [0.218130, 0.347432, 0.550038],
    [0.208623, 0.367752, 0.552675],
    [0.199430, 0.387607, 0.554642],
    [0.190631, 0.407061, 0.556089],
    [0.182256, 0.426184, 0.557120],
    [0.174274, 0.445044, 0.557792],
    [0.166617, 0.463708, 0.558119],
    [0.159194, 0.482237, 0.558073],
    [0.151918, 0.500685, 0.557587],
    [0.144759, 0.519093, 0.556572],
    [0.137770, 0.537492, 0.554906],
    [0.131172, 0.555899, 0.552459],
    [0.125394, 0.574318, 0.549086],
    [0.121148, 0.592739, 0.544641],
    [0.119423, 0.611141, 0.538982],
    [0.121380, 0.629492, 0.531973],
    [0.128087, 0.647749, 0.523491],
    [0.140210, 0.665859, 0.513427],
    [0.157851, 0.683765, 0.501686],
    [0.180653, 0.701402, 0.488189],
    [0.208030, 0.718701, 0.472873],
    [0.239374, 0.735588, 0.455688],
    [0.274149, 0.751988, 0.436601],
    [0.311925, 0.767822, 0.415586],
    [0.352360, 0.783011, 0.392636],
    [0.395174, 0.797475, 0.367757],
    [0.440137, 0.811138, 0.340967],
    [0.487026, 0.823929, 0.312321],
    [0.535621, 0.835785, 0.281908],
    [0.585678, 0.846661, 0.249897],
    [0.636902, 0.856542, 0.216620],
    [0.688944, 0.865448, 0.182725],
    [0.741388, 0.873449, 0.149561],
    [0.793760, 0.880678, 0.120005],
    [0.845561, 0.887322, 0.099702],
    [0.896320, 0.893616, 0.096335],
    [0.945636, 0.899815, 0.112838],
    [0.993248, 0.906157, 0.143936],
];

/// The viridis colour of `t ∈ [0, 1]` (clamped; NaN maps to the low end) as 8-bit sRGB.
pub fn viridis(t: f64) -> [u8; 3] {
    let segments = (VIRIDIS.len() - 1) as f64;
    // `clamp` keeps NaN, and `NaN as usize` is 0, so NaN lands on the first sample.
    let x = t.clamp(0.0, 1.0) * segments;
    let i = (x as usize).min(VIRIDIS.len() - 2);
    let f = if x.is_nan() { 0.0 } else { x - i as f64 };
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    std::array::from_fn(|c| ((a[c] + (b[c] - a[c]) * f) * 255.0).round() as u8)
}

/// The ten colours of Tableau 10 (matplotlib's `tab10`): distinct categorical colours.
const CATEGORICAL: [[u8; 3]; 10] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [127, 127, 127],
    [188, 189, 34],
    [23, 190, 207],
];

/// The colour of segment `i`: Tableau 10 for the first ten, then hues stepped by the golden
/// ratio (`h = 0.618034 i mod 1`, saturation 0.55, value 0.9), which stay apart for any count.
pub fn segment_colour(i: usize) -> [u8; 3] {
    if let Some(&colour) = CATEGORICAL.get(i) {
        return colour;
    }
    let hue = (0.618_033_988_749_895 * i as f64).fract() * 6.0;
    let (saturation, value) = (0.55, 0.9);
    let sector = hue.floor();
    let f = hue - sector;
    let (p, q, t) = (
        value * (1.0 - saturation),
        value * (1.0 - saturation * f),
        value * (1.0 - saturation * (1.0 - f)),
    );
    let rgb = match sector as u32 {
        0 => [value, t, p],
        1 => [q, value, p],
        2 => [p, value, t],
        3 => [p, q, value],
        4 => [t, p, value],
        _ => [value, p, q],
    };
    rgb.map(|c| (c * 255.0).round() as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// CIE L* of an 8-bit sRGB colour (D65).
    fn lightness([r, g, b]: [u8; 3]) -> f64 {
        let linear = |c: u8| {
            let c = f64::from(c) / 255.0;
            if c <= 0.04045 {
                c / 12.92
            } else {
                ((c + 0.055) / 1.055).powf(2.4)
            }
        };
        let y = 0.2126 * linear(r) + 0.7152 * linear(g) + 0.0722 * linear(b);
        if y > 216.0 / 24389.0 {
            116.0 * y.cbrt() - 16.0
        } else {
            y * 24389.0 / 27.0
        }
    }

    #[test]
    fn endpoints_are_viridis_purple_and_yellow() {
        assert_eq!(viridis(0.0), [68, 1, 84]);
        assert_eq!(viridis(1.0), [253, 231, 37]);
        // Out of range and NaN are clamped, not wrapped.
        assert_eq!(viridis(-3.0), viridis(0.0));
        assert_eq!(viridis(7.0), viridis(1.0));
        assert_eq!(viridis(f64::NAN), viridis(0.0));
    }

    #[test]
    fn lightness_increases_monotonically() {
        let samples: Vec<f64> = (0..=200)
            .map(|i| lightness(viridis(f64::from(i) / 200.0)))
            .collect();
        for (i, pair) in samples.windows(2).enumerate() {
            assert!(pair[1] > pair[0], "L* decreases at sample {i}: {pair:?}");
        }
        // The full range is used: dark purple to light yellow.
        assert!(
            samples[0] < 20.0 && samples[200] > 85.0,
            "{} .. {}",
            samples[0],
            samples[200]
        );
    }

    #[test]
    fn segment_colours_are_distinct() {
        let colours: Vec<[u8; 3]> = (0..40).map(segment_colour).collect();
        for i in 0..colours.len() {
            for j in 0..i {
                let d: i32 = (0..3)
                    .map(|c| (i32::from(colours[i][c]) - i32::from(colours[j][c])).abs())
                    .sum();
                assert!(
                    d > 12,
                    "segments {j} and {i}: {:?} {:?}",
                    colours[j],
                    colours[i]
                );
            }
        }
        assert_eq!(segment_colour(0), [31, 119, 180]);
    }
}
