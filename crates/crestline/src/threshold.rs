//! Automatic thresholds: SeekThreshold of Mao, Wang and Zhou (sec. 4.3).
//!
//! Sorted ascending, the values of a shape with features (saliency per vertex, or strength per
//! line) rise slowly along an almost straight part and then steeply; the threshold is where
//! the slope jumps. The paper's search starts at the middle of the sorted list, walks with a
//! coarse step (n/200), stops where one step's rise exceeds 1.3 times the previous step's, and
//! repeats at finer steps around that place.
//!
//! Two guards make the answer robust (the paper leaves this open):
//! - a rise counts only when its slope is also above the mean slope of the upper half, so
//!   jitter on a flat part cannot trigger the 1.3 ratio;
//! - when the upper half is flat (its total rise is below `min_rise` times its median level)
//!   there is no knee — a sphere or a torus — and the answer is `None`: nothing is a feature.

/// Options of [`seek_threshold`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KneeSearch {
    /// Where the search starts, as a fraction of the sorted list. Default: 0.5 (the paper's).
    pub start: f64,
    /// Number of coarse steps over the whole list. Default: 200 (the paper's n/200).
    pub coarse_steps: usize,
    /// Slope jump that marks the knee. Default: 1.3 (the paper's).
    pub slope_ratio: f64,
    /// Relative rise of the upper half below which the curve counts as flat. Default: 0.5.
    pub min_rise: f64,
}

impl Default for KneeSearch {
    fn default() -> Self {
        KneeSearch {
            start: 0.5,
            coarse_steps: 200,
            slope_ratio: 1.3,
            min_rise: 0.5,
        }
    }
}

/// The threshold at the knee of the sorted `values`, or `None` when the curve has no knee.
/// Non-finite values are ignored.
pub fn seek_threshold(values: &[f64], options: &KneeSearch) -> Option<f64> {
    let mut s: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    s.sort_unstable_by(f64::total_cmp);
    let n = s.len();
    if n < 8 {
        return None;
    }
    let lo = ((n as f64 * options.start.clamp(0.0, 0.95)) as usize).min(n - 4);
    let hi = n - 1;
    let median = s[lo].abs().max(s[hi].abs() * 1e-9);
    let rise = s[hi] - s[lo];
    if rise <= options.min_rise * median || rise <= 0.0 {
        return None;
    }
    let mean_slope = rise / (hi - lo) as f64;
    let mut step = (n / options.coarse_steps.max(1)).max(1);
    let (mut from, mut to) = (lo, hi);
    let mut answer = None;
    loop {
        let found = (from + 2 * step..=to).step_by(step).find(|&i| {
            let m = s[i] - s[i - step];
            let m_prev = s[i - step] - s[i - 2 * step];
            m > options.slope_ratio * m_prev && m >= mean_slope * step as f64
        });
        match found {
            Some(i) => {
                answer = Some(s[i - step]);
                if step == 1 {
                    break;
                }
                from = i.saturating_sub(2 * step).max(lo);
                to = i;
                step = (step / 10).max(1);
            }
            None => break,
        }
    }
    answer
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_knee_of_a_flat_then_steep_curve() {
        // 900 flat values in [1, 1.09], then 100 rising steeply from 2 to 12.
        let mut v: Vec<f64> = (0..900).map(|i| 1.0 + i as f64 * 1e-4).collect();
        v.extend((0..100).map(|i| 2.0 + i as f64 * 0.1));
        // Shuffle deterministically: the search must sort.
        v.reverse();
        let t = seek_threshold(&v, &KneeSearch::default()).unwrap();
        assert!((1.08..2.05).contains(&t), "threshold {t}");
        let above = v.iter().filter(|&&x| x > t).count();
        assert!((95..=110).contains(&above), "{above} above");
    }

    #[test]
    fn flat_curves_have_no_knee() {
        let sphere: Vec<f64> = (0..1000)
            .map(|i| 1.0 + ((i * 37) % 101) as f64 * 1e-5)
            .collect();
        assert_eq!(seek_threshold(&sphere, &KneeSearch::default()), None);
        assert_eq!(seek_threshold(&[1.0; 3], &KneeSearch::default()), None);
        assert_eq!(
            seek_threshold(&[f64::NAN; 100], &KneeSearch::default()),
            None
        );
    }

    #[test]
    fn linear_curve_has_no_false_knee_on_jitter() {
        // A straight ramp: every slope equals the mean, so the 1.3 jump never happens.
        let ramp: Vec<f64> = (0..1000).map(|i| i as f64).collect();
        assert_eq!(seek_threshold(&ramp, &KneeSearch::default()), None);
    }
}
