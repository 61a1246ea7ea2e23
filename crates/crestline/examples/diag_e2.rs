//! diag
use crestline::curvature::{CurvatureOptions, Estimator, estimate};
use crestline::shapes::{self, exact};

fn main() {
    for sub in [4u32, 5] {
        let mesh = shapes::ellipsoid(3.0, 2.0, 1.0, sub);
        for (name, est, rings, pre) in [("cf1", Estimator::CubicFit, 1, true), ("cf1-nopre", Estimator::CubicFit, 1, false), ("cf2", Estimator::CubicFit, 2, true), ("cf3", Estimator::CubicFit, 3, true), ("so", Estimator::ShapeOperator, 1, true)] {
            let mut o = CurvatureOptions::default().with_estimator(est).with_rings(rings);
            o.cubic_fit.presmooth = pre;
            let c = estimate(&mesh, &o).unwrap();
            let (mut err, mut norm, mut wrong, mut n) = (0.0, 0.0, 0, 0);
            let mut maxerr: f64 = 0.0;
            for (v, p) in mesh.positions().iter().enumerate() {
                let x = exact::ellipsoid(3.0, 2.0, 1.0, *p);
                if x.k_max - x.k_min < 0.3 { continue; }
                let s = c.dir_max[v].dot(&x.dir_max).signum();
                let d = s * c.e_max[v] - x.e_max;
                err += d * d; norm += x.e_max * x.e_max; maxerr = maxerr.max(d.abs());
                n += 1;
                if x.e_max.abs() > 1.0 && s * c.e_max[v] * x.e_max < 0.0 { wrong += 1; }
            }
            println!("sub {sub} {name}: rel rms {:.3} max {:.2} wrong-sign {wrong}/{n}", (err / norm).sqrt(), maxerr);
        }
    }
}
