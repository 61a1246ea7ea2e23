//! The feature points' threshold per family (our extension of Mao, Wang, Zhou, sec. 4.3).
//!
//! The paper sorts the saliency of every vertex and takes the knee of that one curve
//! (SeekThreshold, [`crate::threshold`]) for ridge and valley points alike. Its own figures
//! choose the two families apart ("top 30% for ridge points, bottom 30% for valley points",
//! Figs. 4 and 6), and with one knee the stronger family decides for both: where the valleys
//! bend less than the ridges (a Gaussian ridge's two feet have about 0.4 of its crest's
//! curvature) no valley vertex reaches the ridges' knee and the shape gets no valley, and on
//! noisy meshes the weaker family's peak saliency sits at the knee, so that it is kept or lost
//! by a hair.
//!
//! Here each family may also have a knee of its own: the same search over the saliency of the
//! vertices whose dominant curvature is of that family's sign (`k_max > |k_min|` for ridges,
//! `k_min < −|k_max|` for valleys; a curve that rises without a knee is split as the whole one
//! is, [`NoKnee::Split`]). A family's threshold is the lower of the knee over all vertices and
//! its own, so that every point the paper's threshold keeps stays a feature point. Its own knee
//! counts only where it stands above the flat part of the whole shape: the value where the
//! paper's search over all vertices starts (the median, the start of
//! [`crate::threshold::KneeSearch`]; [`ChosenThreshold::search_start`]). A family the shape
//! does not have (the valleys of a convex part) is made of the flat vertices that happen to
//! bend its way, whose knee lies down there: on noisy CAD parts such knees sat at the 8th to
//! the 19th percentile of all vertices, those of the height fields' and the public ridge's
//! weaker families at the 70th to the 92nd. The guard is not a clean cut everywhere: the
//! public bumpy sphere's dents, a real but weak valley family, have their knee at the 18th to
//! the 56th percentile and take it on two of its five meshings; and where most vertices lie on
//! planes (CAD parts) the median is about 0 and lets any family knee through (no part lost a
//! line to it). A fixed threshold applies to both families as it is, and a flat saliency (no
//! knee and no split over all vertices: a sphere, a torus) keeps no point.
//!
//! Measured (`score.py --method saliency`, BENCHMARKS.md "The saliency's knee per family"): public
//! cases mean F1 0.941 → 0.961; six height fields not in `../shared` 0.798 → 0.869 (two crossing
//! Gaussian ridges, clean, 0.706 → 0.999: their valleys); 100 noisy surfaces made alike 0.758 →
//! 0.819 (31 up, 2 down by at most 0.012); noisy CAD parts made alike 0.941 → 0.936 (a dome cap
//! 0.615 → 0.542, a keyed shaft 0.962 → 0.929: the ridges' own knee, a few percent under the one
//! over all, lets more noise ridges through on their cylinders).

use crate::curvature::Curvature;
use crate::lines::LineKind;
use crate::threshold::{ChosenThreshold, NoKnee, Threshold, choose_threshold};

/// The saliency thresholds of the feature points, by family.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FamilyThresholds {
    /// The threshold over all vertices (the paper's).
    pub all: ChosenThreshold,
    /// The threshold of ridge points: `all`, or the ridges' own knee where it is lower.
    pub ridge: f64,
    /// The threshold of valley points: `all`, or the valleys' own knee where it is lower.
    pub valley: f64,
}

impl FamilyThresholds {
    /// The threshold of `kind`'s feature points.
    pub fn of(&self, kind: LineKind) -> f64 {
        match kind {
            LineKind::Ridge => self.ridge,
            LineKind::Valley => self.valley,
        }
    }
}

/// The thresholds that `threshold` gives on the per-vertex `saliency` for each family (module
/// docs); `no_knee` as for [`choose_threshold`], for all vertices and for each family.
pub fn family_thresholds(
    saliency: &[f64],
    curvature: &Curvature,
    threshold: &Threshold,
    no_knee: NoKnee,
) -> FamilyThresholds {
    let all = choose_threshold(saliency, threshold, no_knee);
    let same = FamilyThresholds {
        all,
        ridge: all.value,
        valley: all.value,
    };
    // A fixed threshold, or a saliency without a knee or split: one threshold for both.
    if !all.from_knee {
        return same;
    }
    // Where the paper's search over all vertices starts: the top of the shape's flat part.
    let Some(flat_top) = all.search_start else {
        return same;
    };
    let own = |kind: LineKind| {
        let values: Vec<f64> = saliency
            .iter()
            .zip(curvature.k_max.iter().zip(&curvature.k_min))
            .filter(|&(_, (&k_max, &k_min))| match kind {
                LineKind::Ridge => kind.dominates(k_max, k_min),
                LineKind::Valley => kind.dominates(k_min, k_max),
            })
            .map(|(&s, _)| s)
            .collect();
        // A family's curve that rises without a knee is split as the whole one is.
        let knee = choose_threshold(&values, threshold, no_knee).value;
        if knee > flat_top {
            knee.min(all.value)
        } else {
            all.value
        }
    };
    FamilyThresholds {
        all,
        ridge: own(LineKind::Ridge),
        valley: own(LineKind::Valley),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::extract::MwzOptions;

    /// The saliency method's default: the paper's search over all the values.
    fn knee() -> Threshold {
        MwzOptions::automatic()
    }
    const NO_KNEE: NoKnee = NoKnee::Split {
        flat: f64::INFINITY,
    };

    /// The same threshold for both families, not from a knee.
    fn uniform(threshold: f64) -> FamilyThresholds {
        FamilyThresholds {
            all: ChosenThreshold {
                value: threshold,
                from_knee: false,
                from_split: false,
                search_start: None,
            },
            ridge: threshold,
            valley: threshold,
        }
    }

    /// `count` values spread evenly over `[lo, hi]`.
    fn ramp(count: usize, lo: f64, hi: f64) -> impl Iterator<Item = f64> {
        (0..count).map(move |i| lo + (hi - lo) * i as f64 / (count - 1) as f64)
    }

    /// The saliency of ridge-type vertices, then valley-type ones, with their curvature.
    fn shape(ridges: Vec<f64>, valleys: Vec<f64>) -> (Vec<f64>, Curvature) {
        let kinds = ridges.iter().map(|_| (1.0, 0.0));
        let kinds = kinds.chain(valleys.iter().map(|_| (0.0, -1.0)));
        let (k_max, k_min) = kinds.unzip();
        let saliency = ridges.into_iter().chain(valleys).collect();
        let curvature = Curvature {
            k_max,
            k_min,
            ..Default::default()
        };
        (saliency, curvature)
    }

    /// The valleys stand out among the valley-type vertices (a jump above their flat part) but
    /// not among all vertices, whose knee is the ridges' (the valleys lie on the slow rise of
    /// the ridge-type flat vertices): they get their own, lower threshold.
    #[test]
    fn a_weaker_family_gets_its_own_knee() {
        let ridges = ramp(1000, 0.0, 3.0).chain(ramp(50, 10.0, 11.0)).collect();
        let valleys = ramp(1000, 0.0, 1.0).chain(ramp(100, 1.5, 1.6)).collect();
        let (saliency, curvature) = shape(ridges, valleys);
        let t = family_thresholds(&saliency, &curvature, &knee(), NO_KNEE);
        assert!(t.all.from_knee && !t.all.from_split, "{t:?}");
        // The knee over all vertices keeps the ridges and none of the valleys.
        assert!((3.0..10.0).contains(&t.all.value), "{t:?}");
        assert_eq!(t.ridge, t.all.value, "{t:?}");
        // The valleys' own keeps all of theirs and none of their flat part.
        assert!((0.99..1.5).contains(&t.valley), "{t:?}");
        assert_eq!(t.of(LineKind::Valley), t.valley);
    }

    /// A family the shape does not have is made of flat vertices; a knee among them (here at
    /// the valley-type vertices' 80th percentile) lies below the median of all vertices, the
    /// flat part of the whole shape, and is not taken.
    #[test]
    fn a_knee_among_the_flat_vertices_is_not_taken() {
        let ridges = ramp(1000, 0.0, 1.0).chain(ramp(50, 10.0, 11.0)).collect();
        let valleys = ramp(800, 0.0, 0.1)
            .chain(ramp(200, 0.1, 1.0))
            .collect::<Vec<_>>();
        let own = choose_threshold(&valleys, &knee(), NO_KNEE);
        assert!(own.from_knee && own.value < 0.15, "{own:?}");
        let (saliency, curvature) = shape(ridges, valleys);
        let t = family_thresholds(&saliency, &curvature, &knee(), NO_KNEE);
        assert!(t.all.value >= 1.0, "{t:?}");
        assert_eq!(t.ridge, t.all.value, "{t:?}");
        assert_eq!(t.valley, t.all.value, "{t:?}");
    }

    /// A family's own knee lowers only a threshold the search found over all vertices: where
    /// the whole curve has none (here no step is twice as steep as its mean slope) and the
    /// caller's value stands, it stands for both families, though the valleys have a knee.
    #[test]
    fn a_threshold_the_search_did_not_find_stands_for_both_families() {
        let ridges = ramp(1000, 0.0, 2.0).collect();
        let valleys = ramp(900, 0.0, 0.9)
            .chain(ramp(100, 1.5, 1.6))
            .collect::<Vec<_>>();
        let own = choose_threshold(&valleys, &knee(), NoKnee::Value(5.0));
        assert!(own.from_knee && (0.85..1.5).contains(&own.value), "{own:?}");
        let (saliency, curvature) = shape(ridges, valleys);
        let t = family_thresholds(&saliency, &curvature, &knee(), NoKnee::Value(5.0));
        assert!(!t.all.from_knee, "{t:?}");
        assert_eq!((t.all.value, t.ridge, t.valley), (5.0, 5.0, 5.0), "{t:?}");
    }

    #[test]
    fn a_fixed_threshold_and_a_flat_saliency_apply_to_both_families() {
        let (saliency, curvature) = shape(
            ramp(1000, 0.0, 3.0).chain(ramp(50, 10.0, 11.0)).collect(),
            ramp(1000, 0.0, 1.0).chain(ramp(100, 1.5, 1.6)).collect(),
        );
        let fixed = family_thresholds(&saliency, &curvature, &Threshold::Fixed(2.0), NO_KNEE);
        assert_eq!(fixed, uniform(2.0));
        let flat = vec![1.0; saliency.len()];
        let t = family_thresholds(&flat, &curvature, &knee(), NO_KNEE);
        assert_eq!(t, uniform(f64::INFINITY));
    }
}
