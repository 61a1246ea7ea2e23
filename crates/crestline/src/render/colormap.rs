//! Colour maps for per-vertex fields, their value range, and the legend drawn beside them.
//!
//! Two maps, each interpolated linearly in sRGB between a few control points:
//! - [`ColorMap::Viridis`] — perceptually uniform, dark purple to yellow, for fields of one
//!   sign (|k|, saliency, distances). Control points: the nine-step viridis of
//!   S. van der Walt and N. Smith (matplotlib, 2015).
//! - [`ColorMap::Diverging`] — purple, white at 0, green: for signed fields (k_max, k_min,
//!   extremalities). Control points: ColorBrewer's seven-class PRGn (C. Brewer). Its range
//!   is always symmetric about 0, so white means zero. Red and blue are left to the lines.
//!
//! The range is robust by default: the 2nd and 98th percentiles of the finite values, so a
//! few extreme vertices (curvature spikes at degenerate triangles) do not wash the picture
//! out. Values outside the range take the end colours.
//!
//! Limits: interpolating in sRGB rather than a perceptual space bends the lightness ramp a
//! little between control points; with nine (seven) points the error is small.

use super::Rgb;
use super::font;
use crate::error::{Error, Result};

/// A colour map: a function from [0, 1] to colours.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColorMap {
    /// Dark purple (low) through blue and green to yellow (high).
    Viridis,
    /// Purple (negative) through white (zero) to green (positive).
    Diverging,
}

/// Which colour map to use for a field.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ColorMapChoice {
    /// [`ColorMap::Diverging`] when the robust range has values of both signs,
    /// [`ColorMap::Viridis`] otherwise.
    #[default]
    Auto,
    /// Always viridis.
    Viridis,
    /// Always diverging, centred at 0.
    Diverging,
}

/// The field values mapped to the two ends of the colour map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FieldRange {
    /// From the `p`-th to the `(100 - p)`-th percentile of the finite values, `p` in [0, 50).
    Percentile(f64),
    /// Fixed end values (`min < max`).
    Fixed {
        /// Value at the low end.
        min: f64,
        /// Value at the high end.
        max: f64,
    },
}

impl Default for FieldRange {
    fn default() -> Self {
        FieldRange::Percentile(2.0)
    }
}

impl FieldRange {
    /// Checks the percentile or the end values.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a percentile outside [0, 50) or ends that are not finite
    /// and increasing.
    pub fn validate(&self) -> Result<()> {
        match *self {
            FieldRange::Percentile(p) if (0.0..50.0).contains(&p) => Ok(()),
            FieldRange::Percentile(p) => Err(Error::InvalidInput(format!(
                "field range percentile {p} is outside [0, 50)"
            ))),
            FieldRange::Fixed { min, max } if min.is_finite() && max.is_finite() && min < max => {
                Ok(())
            }
            FieldRange::Fixed { min, max } => Err(Error::InvalidInput(format!(
                "field range {min}..{max} must be finite and increasing"
            ))),
        }
    }
}

const VIRIDIS: [Rgb; 9] = [
    [0x44, 0x01, 0x54],
    [0x47, 0x2d, 0x7b],
    [0x3b, 0x52, 0x8b],
    [0x2c, 0x72, 0x8e],
    [0x21, 0x91, 0x8c],
    [0x28, 0xae, 0x80],
    [0x5e, 0xc9, 0x62],
    [0xad, 0xdc, 0x30],
    [0xfd, 0xe7, 0x25],
];

const PURPLE_GREEN: [Rgb; 7] = [
    [0x76, 0x2a, 0x83],
    [0xaf, 0x8d, 0xc3],
    [0xe7, 0xd4, 0xe8],
    [0xf7, 0xf7, 0xf7],
    [0xd9, 0xf0, 0xd3],
    [0x7f, 0xbf, 0x7b],
    [0x1b, 0x78, 0x37],
];

impl ColorMap {
    /// The colour at `t` in [0, 1] (clamped; NaN gives the low end).
    pub fn sample(self, t: f64) -> Rgb {
        let points: &[Rgb] = match self {
            ColorMap::Viridis => &VIRIDIS,
            ColorMap::Diverging => &PURPLE_GREEN,
        };
        let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
        let x = t * (points.len() - 1) as f64;
        let i = (x.floor() as usize).min(points.len() - 2);
        let f = x - i as f64;
        let (a, b) = (points[i], points[i + 1]);
        [0, 1, 2].map(|k| (f64::from(a[k]) * (1.0 - f) + f64::from(b[k]) * f).round() as u8)
    }
}

/// A colour map with the field values at its two ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColorScale {
    /// The map.
    pub map: ColorMap,
    /// Value at the low end.
    pub min: f64,
    /// Value at the high end (`> min`).
    pub max: f64,
}

impl ColorScale {
    /// The scale for `values` under `choice` and `range`; diverging scales are symmetric
    /// about 0. A field whose range is a single value gets a range of ±0.5 around it (±1 for
    /// diverging scales around 0).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when `values` has no finite value or `range` is invalid.
    pub fn for_field(values: &[f64], choice: ColorMapChoice, range: FieldRange) -> Result<Self> {
        range.validate()?;
        let (lo, hi) = match range {
            FieldRange::Fixed { min, max } => (min, max),
            FieldRange::Percentile(p) => percentile_range(values, p).ok_or_else(|| {
                Error::InvalidInput("the field has no finite value to colour by".into())
            })?,
        };
        let map = match choice {
            ColorMapChoice::Viridis => ColorMap::Viridis,
            ColorMapChoice::Diverging => ColorMap::Diverging,
            ColorMapChoice::Auto if lo < 0.0 && hi > 0.0 => ColorMap::Diverging,
            ColorMapChoice::Auto => ColorMap::Viridis,
        };
        let (min, max) = match map {
            ColorMap::Diverging => {
                let m = lo.abs().max(hi.abs());
                if m > 0.0 { (-m, m) } else { (-1.0, 1.0) }
            }
            ColorMap::Viridis if hi > lo => (lo, hi),
            ColorMap::Viridis => (lo - 0.5, hi + 0.5),
        };
        Ok(ColorScale { map, min, max })
    }

    /// The colour of value `v`; `None` for a non-finite value.
    pub fn color(&self, v: f64) -> Option<Rgb> {
        v.is_finite()
            .then(|| self.map.sample((v - self.min) / (self.max - self.min)))
    }
}

/// The `p`-th and `(100 - p)`-th percentiles of the finite values (nearest rank), or `None`
/// when there is no finite value.
pub fn percentile_range(values: &[f64], p: f64) -> Option<(f64, f64)> {
    let mut finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    if finite.is_empty() {
        return None;
    }
    let last = finite.len() - 1;
    let rank = |q: f64| ((q / 100.0 * last as f64).round() as usize).min(last);
    let (lo_rank, hi_rank) = (rank(p.clamp(0.0, 50.0)), rank(100.0 - p.clamp(0.0, 50.0)));
    let lo = *finite.select_nth_unstable_by(lo_rank, f64::total_cmp).1;
    let hi = *finite.select_nth_unstable_by(hi_rank, f64::total_cmp).1;
    Some((lo, hi))
}

/// Width in pixels of the strip at the right of the image kept for the legend (at most
/// half the image).
pub fn legend_width(width: usize, height: usize) -> usize {
    (width.min(height) * 20 / 100).max(48).min(width / 2)
}

/// Draws the legend into the right strip of `rgba`: a vertical colour bar, the values at
/// its ends (and 0 at its middle for a diverging scale) and the title above.
pub fn draw_legend(rgba: &mut [u8], width: usize, height: usize, scale: &ColorScale, title: &str) {
    let strip = legend_width(width, height);
    let text_scale = (width.min(height) / 300).max(1);
    let bar_w = (strip / 6).max(4);
    let bar_h = height / 2;
    let x0 = width - strip + strip / 10;
    let y0 = (height - bar_h) / 2;
    let mut put = |x: usize, y: usize, c: Rgb| {
        if x < width && y < height {
            let i = (y * width + x) * 4;
            rgba[i..i + 3].copy_from_slice(&c);
        }
    };
    let frame: Rgb = [60, 60, 60];
    for y in y0.saturating_sub(1)..=y0 + bar_h {
        for x in x0.saturating_sub(1)..=x0 + bar_w {
            let inside = y >= y0 && y < y0 + bar_h && x >= x0 && x < x0 + bar_w;
            let color = if inside {
                let t = 1.0 - (y - y0) as f64 / (bar_h.max(2) - 1) as f64;
                scale.map.sample(t)
            } else {
                frame
            };
            put(x, y, color);
        }
    }
    let ink: Rgb = [20, 20, 20];
    let label_x = x0 + bar_w + 3 * text_scale;
    let glyph_h = font::GLYPH_HEIGHT * text_scale;
    let mut labels = vec![
        (format_value(scale.max), y0),
        (
            format_value(scale.min),
            (y0 + bar_h).saturating_sub(glyph_h),
        ),
    ];
    if scale.map == ColorMap::Diverging {
        labels.push(("0".to_string(), y0 + bar_h / 2 - glyph_h / 2));
    }
    for (text, y) in labels {
        font::draw_text(&mut put, &text, label_x, y, text_scale, ink);
    }
    if !title.is_empty() {
        let w = font::text_width(title, text_scale);
        let x = (x0 + bar_w / 2)
            .saturating_sub(w / 2)
            .min(width.saturating_sub(w + 2));
        let y = y0.saturating_sub(glyph_h + 4 * text_scale);
        font::draw_text(&mut put, title, x, y, text_scale, ink);
    }
}

/// A value with three significant digits: `0.0123`, `12.3`, `1.23e-5`.
pub fn format_value(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { format!("{v}") };
    }
    let exponent = v.abs().log10().floor() as i32;
    if (-3..4).contains(&exponent) {
        let decimals = (2 - exponent).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.2e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_hit_their_control_points() {
        assert_eq!(ColorMap::Viridis.sample(0.0), VIRIDIS[0]);
        assert_eq!(ColorMap::Viridis.sample(1.0), VIRIDIS[8]);
        assert_eq!(ColorMap::Viridis.sample(0.5), VIRIDIS[4]);
        assert_eq!(ColorMap::Diverging.sample(0.5), [0xf7; 3]);
        assert_eq!(ColorMap::Viridis.sample(-3.0), VIRIDIS[0]);
        assert_eq!(ColorMap::Viridis.sample(f64::NAN), VIRIDIS[0]);
    }

    #[test]
    fn viridis_gets_lighter_monotonically() {
        let luma = |c: Rgb| 0.2126 * c[0] as f64 + 0.7152 * c[1] as f64 + 0.0722 * c[2] as f64;
        let samples: Vec<f64> = (0..=100)
            .map(|i| luma(ColorMap::Viridis.sample(i as f64 / 100.0)))
            .collect();
        assert!(samples.windows(2).all(|w| w[1] >= w[0] - 0.5));
    }

    #[test]
    fn percentiles_ignore_outliers_and_non_finite_values() {
        let mut v: Vec<f64> = (0..=100).map(f64::from).collect();
        v.push(f64::NAN);
        v.push(f64::INFINITY);
        v[50] = 1e9;
        // 101 finite values: 0..=49, 51..=100 and the outlier; ranks 2 and 98 of 0..=100.
        let (lo, hi) = percentile_range(&v, 2.0).unwrap();
        assert_eq!((lo, hi), (2.0, 99.0));
        assert_eq!(percentile_range(&[f64::NAN], 2.0), None);
    }

    #[test]
    fn signed_fields_get_a_symmetric_diverging_scale() {
        let v = [-1.0, -0.5, 0.0, 2.0];
        let s =
            ColorScale::for_field(&v, ColorMapChoice::Auto, FieldRange::Percentile(0.0)).unwrap();
        assert_eq!(s.map, ColorMap::Diverging);
        assert_eq!((s.min, s.max), (-2.0, 2.0));
        assert_eq!(s.color(0.0), Some([0xf7; 3]));
        let s = ColorScale::for_field(
            &[1.0, 3.0],
            ColorMapChoice::Auto,
            FieldRange::Percentile(0.0),
        )
        .unwrap();
        assert_eq!(s.map, ColorMap::Viridis);
        assert_eq!((s.min, s.max), (1.0, 3.0));
        assert_eq!(s.color(f64::NAN), None);
        let flat =
            ColorScale::for_field(&[2.0; 4], ColorMapChoice::Auto, FieldRange::default()).unwrap();
        assert!(flat.max > flat.min);
        assert!(
            ColorScale::for_field(&[f64::NAN], ColorMapChoice::Auto, FieldRange::default())
                .is_err()
        );
    }

    #[test]
    fn values_print_with_three_significant_digits() {
        assert_eq!(format_value(0.0), "0");
        assert_eq!(format_value(12.345), "12.3");
        assert_eq!(format_value(-0.012345), "-0.0123");
        assert_eq!(format_value(1234.5), "1234");
        assert_eq!(format_value(12345.0), "1.23e4");
        assert_eq!(format_value(-1.5e-5), "-1.50e-5");
    }
}
