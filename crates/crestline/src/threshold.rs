//! Automatic thresholds: SeekThreshold of Mao, Wang and Zhou (sec. 4.3).
//!
//! Sorted ascending, the values of a shape with features (saliency per vertex, or strength per
//! line) rise slowly along an almost straight part and then steeply; the threshold is where
//! the slope jumps. The paper's search starts at the middle of the sorted list, walks with a
//! coarse step (n/200), stops where one step's rise exceeds 1.3 times the previous step's, and
//! repeats at finer steps (a tenth each time) around that place. The threshold is the value
//! where the steep step starts.
//!
//! The paper leaves open what happens on noisy or featureless data; three guards make the
//! answer robust:
//! - **steepness**: a jump counts only when the step is also steeper than
//!   [`KneeSearch::steepness`] (default 2) times the mean slope of the searched part, so jitter
//!   on the slowly rising part cannot trigger the 1.3 ratio. Measured on fandisk's saliency
//!   (cubic-fit curvature): with the plain 1.3 rule, or a factor of 1, the search stops at
//!   ≈ 70% of the list, among the flat vertices next to the creases (whose Var term is large);
//!   with 2 (or 3) at 88%, where the crease vertices begin;
//! - **tail**: the top [`KneeSearch::tail_steps`] coarse steps (default 1, the top 0.5%) are
//!   left out of the mean slope, so that a few extreme values (fandisk's corners have 6× the
//!   saliency of its creases) do not set the scale; they are still searched, so a shape whose
//!   features are fewer than 0.5% of its vertices (a finely meshed cube) keeps them;
//! - **no knee**: when the searched part is flat — its total rise is below
//!   [`KneeSearch::min_rise`] times its lowest value — the answer is `None`: nothing stands out
//!   (a sphere, a torus). This test spans the whole searched part, tail included.
//!
//! Line strengths (HPW and YBS lines) span several orders of magnitude; [`Scale::Log`]
//! searches their logarithms, where the flatness test reads as a ratio
//! (`max / min ≤ 1 + min_rise`).
//!
//! **A curve that rises without a knee** (our extension, [`NoKnee::Split`], the saliency
//! method's default). The paper's search presumes a slowly rising part and a steep one. A
//! shape whose features are broad and rounded has neither: its sorted saliency rises as one
//! ramp (a superquadric whose edges are rounded over a fifth of its vertices: from the median
//! to the top almost straight), the search finds a knee only where jitter happens to make
//! one, and then anywhere from the 53rd to the 99th percentile, or none, and the shape gets
//! no line. Where the searched part is not flat but has no knee, [`split_threshold`] splits it
//! in two by Otsu's rule (the split that maximises the variance between the two classes;
//! N. Otsu, *A threshold selection method from gray-level histograms*, IEEE SMC 9, 1979),
//! which asks for no constant. Measured (`score.py`, saliency method): on the public
//! superquadrics the knee found lies between 0.60 and 1.29 and the split at 0.90 to 1.03,
//! with the same F1; on six noisy superquadrics made alike (not in `../shared`) one had no
//! knee (no line, F1 0) and gets 0.98 from the split, like the other five.

/// On which scale the sorted values are searched.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scale {
    /// The values themselves (saliency).
    #[default]
    Linear,
    /// Their natural logarithms; values `<= 0` are left out (line strengths).
    Log,
}

/// Options of [`seek_threshold`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KneeSearch {
    /// Where the search starts, as a fraction of the sorted list. Default: 0.5 (the paper's).
    pub start: f64,
    /// Number of coarse steps over the whole list. Default: 200 (the paper's n/200).
    pub coarse_steps: usize,
    /// Slope jump that marks the knee. Default: 1.3 (the paper's).
    pub slope_ratio: f64,
    /// A jump counts only when its step is this many times steeper than the mean slope of
    /// the searched part. Default: 2.
    pub steepness: f64,
    /// Coarse steps at the top of the list left out of the mean slope. Default: 1.
    pub tail_steps: usize,
    /// Relative rise of the searched part below which the curve counts as flat. Default: 0.5.
    pub min_rise: f64,
    /// The scale searched. Default: [`Scale::Linear`].
    pub scale: Scale,
}

impl Default for KneeSearch {
    fn default() -> Self {
        KneeSearch {
            start: 0.5,
            coarse_steps: 200,
            slope_ratio: 1.3,
            steepness: 2.0,
            tail_steps: 1,
            min_rise: 0.5,
            scale: Scale::Linear,
        }
    }
}

impl KneeSearch {
    /// The search for line strengths: on [`Scale::Log`], over the whole list (`start` 0),
    /// since the lines handed in are already the candidates (see [`crate::extract`]).
    pub fn for_strengths() -> Self {
        KneeSearch {
            start: 0.0,
            scale: Scale::Log,
            ..Default::default()
        }
    }
}

/// A threshold on values where larger is stronger (line strengths, saliency): fixed, or
/// chosen by the knee search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Threshold {
    /// Keep the values at least this.
    Fixed(f64),
    /// The knee of the sorted values at or above `floor` ([`seek_threshold`] with `search`),
    /// never below `floor`. The floor keeps shapes without features empty: among their weak
    /// values a knee is easily found.
    Knee {
        /// The values searched are those at least this; the threshold is never below it.
        floor: f64,
        /// The knee search.
        search: KneeSearch,
    },
}

impl Threshold {
    /// True for a knee search.
    pub fn is_auto(&self) -> bool {
        matches!(self, Threshold::Knee { .. })
    }

    /// The fixed value, or the knee search's floor.
    pub fn floor(&self) -> f64 {
        match *self {
            Threshold::Fixed(t) => t,
            Threshold::Knee { floor, .. } => floor,
        }
    }
}

/// What [`choose_threshold`] chose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChosenThreshold {
    /// The threshold.
    pub value: f64,
    /// True when it is the knee of the values, or their split when they rose without a knee
    /// (false when fixed, or when the values had no knee and no split was asked for or they
    /// were flat).
    pub from_knee: bool,
    /// True when the values had no knee and the threshold is their split
    /// ([`NoKnee::Split`], [`split_threshold`]).
    pub from_split: bool,
    /// Where the knee search started: the value at `start` of the sorted values at or above
    /// the floor, the top of the slowly rising part the paper's search skips. `None` for a
    /// fixed threshold, or when the searched part was flat or had fewer than 8 values.
    pub search_start: Option<f64>,
}

/// What [`choose_threshold`] answers when the values have no knee.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NoKnee {
    /// This value (the line pipelines keep their floor).
    Value(f64),
    /// The split of the searched part ([`split_threshold`]) when it rises; `flat` when it is
    /// flat or has fewer than 8 values (the saliency method: `f64::INFINITY`, no point on a
    /// sphere or a torus).
    Split {
        /// The threshold of a flat curve.
        flat: f64,
    },
}

/// The automatic threshold step: the threshold that `threshold` gives on `values`. A fixed
/// threshold is itself; a knee search gives the knee of the values at or above its floor,
/// raised to the floor, or what `no_knee` says when they have none (the line pipelines keep
/// the floor; the saliency method splits a rising curve and keeps no point of a flat one).
pub fn choose_threshold(values: &[f64], threshold: &Threshold, no_knee: NoKnee) -> ChosenThreshold {
    match *threshold {
        Threshold::Fixed(value) => ChosenThreshold {
            value,
            from_knee: false,
            from_split: false,
            search_start: None,
        },
        Threshold::Knee { floor, search } => {
            let candidates: Vec<f64> = values.iter().copied().filter(|&t| t >= floor).collect();
            // Sorted once for the knee and the split.
            let part = searched_part(&candidates, &search);
            let chosen = |value: f64, from_knee: bool, from_split: bool| ChosenThreshold {
                value,
                from_knee,
                from_split,
                search_start: part.as_ref().map(|p| p.sorted[p.lo]),
            };
            if let Some(knee) = part.as_ref().and_then(|p| p.knee(&search)) {
                return chosen(floor.max(knee), true, false);
            }
            match no_knee {
                NoKnee::Value(value) => chosen(value, false, false),
                NoKnee::Split { flat } => match part.as_ref().and_then(Searched::split) {
                    Some(split) => chosen(floor.max(split), true, true),
                    None => chosen(flat, false, false),
                },
            }
        }
    }
}

/// The values searched by [`seek_threshold`] and [`split_threshold`].
struct Searched {
    /// The finite values sorted ascending (on the log scale, those `> 0`).
    sorted: Vec<f64>,
    /// The same on the scale searched.
    s: Vec<f64>,
    /// The index where the search starts.
    lo: usize,
}

/// The values of `values` as the searches read them; `None` when there are fewer than 8 or
/// the searched part is flat (its rise from `start` to the top below `min_rise`, see the
/// module docs).
fn searched_part(values: &[f64], options: &KneeSearch) -> Option<Searched> {
    let mut sorted: Vec<f64> = values
        .iter()
        .copied()
        .filter(|v| v.is_finite() && (options.scale == Scale::Linear || *v > 0.0))
        .collect();
    sorted.sort_unstable_by(f64::total_cmp);
    // The values on the scale searched; the threshold is one of the values themselves (not
    // `exp(ln v)`, which can round above v and drop the value at the knee).
    let s: Vec<f64> = match options.scale {
        Scale::Linear => sorted.clone(),
        Scale::Log => sorted.iter().map(|v| v.ln()).collect(),
    };
    let n = s.len();
    if n < 8 {
        return None;
    }
    let lo = ((n as f64 * options.start.clamp(0.0, 0.95)) as usize).min(n - 4);
    let rise = s[n - 1] - s[lo];
    let flat = match options.scale {
        Scale::Linear => rise <= options.min_rise * s[lo].abs().max(s[n - 1].abs() * 1e-9),
        Scale::Log => rise <= options.min_rise.ln_1p(),
    };
    if flat || rise.is_nan() || rise <= 0.0 {
        return None;
    }
    Some(Searched { sorted, s, lo })
}

/// The threshold that splits the searched part of the sorted `values` (from `start` to the
/// top, on the scale searched) in two by Otsu's rule: the largest value of the lower class,
/// for the split that maximises `w0 w1 (m0 − m1)²` (class weights and means). `None` when the
/// part is flat or has fewer than 8 values, as for [`seek_threshold`]. Values above the
/// threshold are the salient ones.
pub fn split_threshold(values: &[f64], options: &KneeSearch) -> Option<f64> {
    searched_part(values, options)?.split()
}

/// The threshold at the knee of the sorted `values`, or `None` when the curve has no knee.
/// Values above the threshold are the salient ones. Non-finite values (and, on the log
/// scale, values `<= 0`) are ignored; fewer than 8 values have no knee.
pub fn seek_threshold(values: &[f64], options: &KneeSearch) -> Option<f64> {
    searched_part(values, options)?.knee(options)
}

impl Searched {
    /// [`split_threshold`] of these values.
    fn split(&self) -> Option<f64> {
        let Searched { sorted, s, lo } = self;
        let lo = *lo;
        let part = &s[lo..];
        let n = part.len() as f64;
        let total: f64 = part.iter().sum();
        let (mut below, mut best, mut split) = (0.0, f64::NEG_INFINITY, None);
        // The lower class is part[..i], i = 1..len: equal values stay in one class.
        for i in 1..part.len() {
            below += part[i - 1];
            if part[i] == part[i - 1] {
                continue;
            }
            let (n0, n1) = (i as f64, n - i as f64);
            let gap = below / n0 - (total - below) / n1;
            let between = n0 * n1 * gap * gap;
            if between > best {
                best = between;
                split = Some(sorted[lo + i - 1]);
            }
        }
        split
    }

    /// [`seek_threshold`] of these values.
    fn knee(&self, options: &KneeSearch) -> Option<f64> {
        let Searched { sorted, s, lo } = self;
        let lo = *lo;
        let n = s.len();
        let coarse = (n / options.coarse_steps.max(1)).max(1);
        let hi = (n - 1)
            .saturating_sub(options.tail_steps * coarse)
            .max(lo + 3);
        let steep = options.steepness * (s[hi] - s[lo]) / (hi - lo) as f64;
        let mut step = coarse;
        let (mut from, mut to) = (lo, n - 1);
        let mut answer = None;
        loop {
            let found = (from + 2 * step..=to).step_by(step).find(|&i| {
                let m = s[i] - s[i - step];
                let m_prev = s[i - step] - s[i - 2 * step];
                m > options.slope_ratio * m_prev && m >= steep * step as f64
            });
            match found {
                Some(i) => {
                    answer = Some(sorted[i - step]);
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
    fn the_threshold_is_one_of_the_values() {
        // Strengths on the log scale: the knee is the value where the steep part starts, so
        // the line with that strength is kept. Returned as `exp(ln v)` it rounded above v for
        // some v (3.061008 on the bumpy sphere, YBS) and that line was dropped.
        for k in 0..200 {
            let scale = 1.0 + k as f64 * 1.37e-3;
            let v: Vec<f64> = [
                1.19089, 1.45731, 1.77526, 3.06101, 8.25576, 8.29944, 17.7988, 17.8301,
            ]
            .iter()
            .map(|x| x * scale)
            .collect();
            let t = seek_threshold(&v, &KneeSearch::for_strengths()).unwrap();
            assert!(v.contains(&t), "threshold {t} is none of {v:?}");
        }
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
        let strengths = KneeSearch::for_strengths();
        assert_eq!(seek_threshold(&[0.0; 100], &strengths), None);
        // max / min = 1.4 < 1.5 on the log scale.
        let narrow: Vec<f64> = (0..100).map(|i| 1.0 + 0.004 * i as f64).collect();
        assert_eq!(seek_threshold(&narrow, &strengths), None);
    }

    #[test]
    fn linear_curve_has_no_false_knee_on_jitter() {
        // A straight ramp: every slope equals the mean, so the 1.3 jump never happens.
        let ramp: Vec<f64> = (0..1000).map(|i| i as f64).collect();
        assert_eq!(seek_threshold(&ramp, &KneeSearch::default()), None);
        // The same ramp with ±20% jitter on every step: the ratio 1.3 is met all along,
        // the steepness never.
        let mut x = 0.0;
        let jittered: Vec<f64> = (0..1000)
            .map(|i| {
                x += 1.0 + 0.2 * ((i * 7919 % 13) as f64 / 6.0 - 1.0);
                x
            })
            .collect();
        assert_eq!(seek_threshold(&jittered, &KneeSearch::default()), None);
    }

    #[test]
    fn a_few_extreme_values_do_not_hide_the_knee() {
        // Fandisk-like: a flat part, a steep rise into a second plateau (the creases),
        // then 0.3% extreme values (the corners) 100 times higher.
        let mut v: Vec<f64> = (0..8000).map(|i| 1.0 + i as f64 * 1e-4).collect();
        v.extend((0..500).map(|i| 2.0 + i as f64 * 0.01));
        v.extend((0..1470).map(|i| 7.0 + i as f64 * 1e-3));
        v.extend((0..30).map(|i| 800.0 + i as f64));
        let t = seek_threshold(&v, &KneeSearch::default()).unwrap();
        assert!((1.7..2.1).contains(&t), "threshold {t}");
    }

    #[test]
    fn features_in_the_tail_are_found() {
        // A finely meshed cube: the flat faces have saliency 0, the 0.3% crease vertices 1 to 2.
        let mut v = vec![0.0; 10_000];
        v.extend((0..30).map(|i| 1.0 + i as f64 / 30.0));
        let t = seek_threshold(&v, &KneeSearch::default()).unwrap();
        assert!((0.0..1.0).contains(&t), "threshold {t}");
        assert_eq!(v.iter().filter(|&&x| x > t).count(), 30);
    }

    /// 40 weak lines with strengths 1..10 spread evenly in log, 10 strong ones 100..1000.
    fn weak_and_strong_strengths() -> Vec<f64> {
        let mut v: Vec<f64> = (0..40).map(|i| 10f64.powf(i as f64 / 40.0)).collect();
        v.extend((0..10).map(|i| 100.0 * 10f64.powf(i as f64 / 10.0)));
        v
    }

    #[test]
    fn log_scale_finds_the_gap_between_weak_and_strong_lines() {
        let v = weak_and_strong_strengths();
        let t = seek_threshold(&v, &KneeSearch::for_strengths()).unwrap();
        assert!((8.0..100.0).contains(&t), "threshold {t}");
        assert_eq!(v.iter().filter(|&&x| x > t).count(), 10);
    }

    #[test]
    fn choose_threshold_keeps_a_fixed_one_and_raises_a_knee_to_its_floor() {
        let v = weak_and_strong_strengths();
        let fixed = choose_threshold(&v, &Threshold::Fixed(3.0), NoKnee::Value(0.0));
        assert_eq!((fixed.value, fixed.from_knee), (3.0, false));
        let search = KneeSearch::for_strengths();
        let knee = choose_threshold(
            &v,
            &Threshold::Knee { floor: 0.5, search },
            NoKnee::Value(0.5),
        );
        assert!(
            knee.from_knee && !knee.from_split && (8.0..100.0).contains(&knee.value),
            "{knee:?}"
        );
        // Above a floor among the strong values the knee is raised to the floor or beyond.
        let high = choose_threshold(
            &v,
            &Threshold::Knee {
                floor: 50.0,
                search,
            },
            NoKnee::Value(50.0),
        );
        assert!(high.value >= 50.0, "{high:?}");
        // No knee: the value given for that case.
        let flat = vec![1.0; 100];
        let none = choose_threshold(
            &flat,
            &Threshold::Knee { floor: 0.0, search },
            NoKnee::Value(f64::INFINITY),
        );
        assert_eq!((none.value, none.from_knee), (f64::INFINITY, false));
        // A flat curve is not split either.
        let none = choose_split(&flat, search);
        assert_eq!(
            (none.value, none.from_knee, none.from_split),
            (f64::INFINITY, false, false)
        );
    }

    /// The saliency method's choice: the knee above 0, else the split, else infinity.
    fn choose_split(values: &[f64], search: KneeSearch) -> ChosenThreshold {
        let no_knee = NoKnee::Split {
            flat: f64::INFINITY,
        };
        choose_threshold(values, &Threshold::Knee { floor: 0.0, search }, no_knee)
    }

    /// A superquadric's sorted saliency: a flat face (0 to 0.3), then a ramp from the median
    /// to the top with a little jitter, and no knee.
    fn ramp_without_knee() -> Vec<f64> {
        let mut v: Vec<f64> = (0..4000).map(|i| 0.3 * i as f64 / 4000.0).collect();
        v.extend((0..6000).map(|i| {
            let jitter = 0.002 * (((i * 7919) % 11) as f64 / 5.0 - 1.0);
            0.55 + 0.8 * i as f64 / 6000.0 + jitter
        }));
        v
    }

    #[test]
    fn a_ramp_without_knee_is_split_in_two() {
        let v = ramp_without_knee();
        let search = KneeSearch::default();
        assert_eq!(seek_threshold(&v, &search), None);
        // The split of the upper half, a uniform ramp from 0.68 to 1.35: its middle.
        let t = split_threshold(&v, &search).unwrap();
        assert!((1.0..1.03).contains(&t), "split {t}");
        assert!(v.contains(&t));
        let chosen = choose_split(&v, search);
        assert_eq!(
            (chosen.value, chosen.from_knee, chosen.from_split),
            (t, true, true)
        );
        // The line pipelines keep their floor.
        let floor = choose_threshold(
            &v,
            &Threshold::Knee { floor: 0.0, search },
            NoKnee::Value(0.0),
        );
        assert_eq!((floor.value, floor.from_split), (0.0, false));
        // A knee, where there is one, wins over the split.
        let v = weak_and_strong_strengths();
        let search = KneeSearch::for_strengths();
        let knee = choose_threshold(
            &v,
            &Threshold::Knee { floor: 0.5, search },
            NoKnee::Split { flat: 0.5 },
        );
        assert!(knee.from_knee && !knee.from_split, "{knee:?}");
    }

    #[test]
    fn otsu_split_separates_two_groups() {
        // Two clusters in the upper half: the split is the top of the lower one, whatever
        // their sizes.
        let mut v = vec![0.0; 1000];
        v.extend((0..700).map(|i| 1.0 + i as f64 * 1e-4));
        v.extend((0..300).map(|i| 3.0 + i as f64 * 1e-4));
        let t = split_threshold(&v, &KneeSearch::default()).unwrap();
        assert_eq!(t, 1.0 + 699.0 * 1e-4);
        // Flat, too few or not finite: no split.
        let search = KneeSearch::default();
        assert_eq!(split_threshold(&[1.0; 100], &search), None);
        assert_eq!(split_threshold(&[1.0, 2.0, 3.0], &search), None);
        assert_eq!(split_threshold(&[f64::NAN; 100], &search), None);
    }
}
