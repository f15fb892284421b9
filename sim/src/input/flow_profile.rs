//! Streaming velocity profile `u(y)` of the inhomogeneous (Kolmogorov-type) flow, docs/physics.md section 2.
//!
//! The user gives `u(y)` as an expression over `y` with the constants `L` (= L_y) and `pi`
//! (exmex's own constants `PI`, `π`, `E`, `e`, `TAU`, `τ` are also accepted). The expression
//! is evaluated once, at construction, into a periodic table of `u`, `u'` and `u''`; the
//! simulator then reads `u` and `u'` by cubic Hermite interpolation, which is cheap enough
//! for every particle at every step.
//!
//! Units: `y` and `L_y` in particle radii `a`; `u` in `a` per unit time; `u'` in 1/time.

use crate::error::SimError;
use crate::input::profile_syntax::{check_function_names, locate_syntax_error, ScientificNumber};
use exmex::prelude::*;
use exmex::FloatOpsFactory;

/// A parsed expression: exmex's operators, numbers with exponents (`1e-3`).
type Expr = FlatEx<f64, FloatOpsFactory<f64>, ScientificNumber>;

/// Table intervals per period. Cubic Hermite interpolation from exact values and slopes errs
/// by at most `h^4/384 * max|f''''|` with `h = L_y / TABLE_INTERVALS`; for
/// `u = A sin(2 pi m y / L_y)` that is `1.4e-14 * m^4 * A` (and the same bound relative to
/// `max|u'|` for the slope), so for the profiles of docs/physics.md section 8 the table is exact to
/// round-off.
const TABLE_INTERVALS: usize = 4096;

/// Largest accepted interpolation error at the interval midpoints, relative to `max|u|`
/// (for `u`) and `max|u'|` (for `u'`). Smooth profiles stay many orders below it; a pole
/// between two table nodes, a kink, or an oscillation too fast for the table exceeds it.
const TABLE_TOLERANCE: f64 = 1e-6;

/// Periodicity check: `|u(L_y) - u(0)| <= PERIODIC_TOLERANCE * max|u|` and
/// `|u'(L_y) - u'(0)| <= PERIODIC_TOLERANCE * max|u'|`. Round-off in a truly periodic
/// expression is ~1e-15 relative; any real mismatch of the period is far above 1e-8.
const PERIODIC_TOLERANCE: f64 = 1e-8;

/// Cubic Hermite basis at fraction `t` of an interval of length `h`: weights of the left
/// value, left slope, right value, right slope.
#[inline]
fn hermite_weights(t: f64, h: f64) -> [f64; 4] {
    let (t2, t3) = (t * t, t * t * t);
    [
        2.0 * t3 - 3.0 * t2 + 1.0,
        (t3 - 2.0 * t2 + t) * h,
        3.0 * t2 - 2.0 * t3,
        (t3 - t2) * h,
    ]
}

/// Step of the finite-difference fallback, relative to `L_y`.
const FD_STEP: f64 = 1e-3;

/// The variables an expression may use; anything else is an unknown symbol.
const ALLOWED_VARIABLES: [&str; 3] = ["y", "L", "pi"];

/// A periodic streaming velocity profile `u(y)` along x (docs/physics.md section 2), tabulated over one
/// period `[0, L_y)` and read at any real `y` by periodic wrapping.
#[derive(Debug, Clone)]
pub struct FlowProfile {
    expr: String,
    l_y: f64,
    /// Table spacing `h = L_y / TABLE_INTERVALS`.
    spacing: f64,
    /// `[u, u', u'']` at `y = i h`, `i = 0..=TABLE_INTERVALS`; the last node repeats the first.
    nodes: Vec<[f64; 3]>,
    max_abs_u: f64,
    max_abs_shear_rate: f64,
}

impl FlowProfile {
    /// Parses `expr` as `u(y)` for a box of height `l_y` (in `a`) and tabulates it.
    ///
    /// `u'` and `u''` come from exmex's symbolic partial derivatives; only for an
    /// expression using an operator exmex cannot differentiate (`abs`, `min`, `max`,
    /// `floor`, ...) they fall back to 4th-order central differences of step
    /// `1e-3 L_y` (relative error ~`(2 pi m 1e-3)^4 / 30` for a mode `m`).
    ///
    /// Refuses: `l_y` not finite and positive; an expression that does not parse, uses a
    /// variable other than `y`, `L`, `pi`, or is not finite somewhere on `[0, L_y]`; a
    /// profile that the table cannot resolve (see `TABLE_TOLERANCE`: poles, kinks); a
    /// profile not periodic in `L_y` (see `PERIODIC_TOLERANCE`).
    pub fn new(expr: &str, l_y: f64) -> Result<FlowProfile, SimError> {
        if !(l_y.is_finite() && l_y > 0.0) {
            return Err(SimError::Field {
                field: "L_y".into(),
                message: format!("must be finite and positive, got {l_y}"),
            });
        }
        let fail = |message: String| SimError::Profile {
            expr: expr.into(),
            message,
        };
        let exact = Exact::parse(expr, l_y).map_err(fail)?;
        let spacing = l_y / TABLE_INTERVALS as f64;
        let nodes = (0..=TABLE_INTERVALS)
            .map(|i| exact.at(i as f64 * spacing))
            .collect::<Result<Vec<_>, _>>()
            .map_err(fail)?;
        let max_abs = |k: usize| nodes.iter().fold(0.0_f64, |m, node| m.max(node[k].abs()));
        let mut profile = FlowProfile {
            expr: expr.into(),
            l_y,
            spacing,
            max_abs_u: max_abs(0),
            max_abs_shear_rate: max_abs(1),
            nodes,
        };
        profile.check_resolution(&exact).map_err(fail)?;
        profile.check_periodic().map_err(fail)?;
        profile.nodes[TABLE_INTERVALS] = profile.nodes[0];
        Ok(profile)
    }

    /// The affine velocity `u(y) = gdot (y - L_y/2)` of homogeneous simple shear across a
    /// Lees-Edwards box of height `l_y` (docs/physics.md section 10), on `[0, L_y)`: zero
    /// mean over the box, and the jump of `-gdot L_y` at the y faces (a sawtooth when
    /// wrapped) is the velocity of the sliding image. Tabulated like any profile (the
    /// Hermite table of a linear function is exact); its expression is `gdot*(y-L/2)`.
    /// `gdot` must be finite and positive, `l_y` too (checked by the scene).
    pub fn simple_shear(gdot: f64, l_y: f64) -> FlowProfile {
        let spacing = l_y / TABLE_INTERVALS as f64;
        let nodes = (0..=TABLE_INTERVALS)
            .map(|i| [gdot * (i as f64 * spacing - 0.5 * l_y), gdot, 0.0])
            .collect();
        FlowProfile {
            expr: format!("{gdot}*(y-L/2)"),
            l_y,
            spacing,
            nodes,
            max_abs_u: 0.5 * gdot * l_y,
            max_abs_shear_rate: gdot,
        }
    }

    /// Streaming velocity `u(y)` (units `a`/time) at any real `y`, wrapped into `[0, L_y)`.
    /// A non-finite `y` gives NaN.
    pub fn u(&self, y: f64) -> f64 {
        self.interpolate(y, 0)
    }

    /// Mean of `u` over `[lo, hi]` (a/time): the streaming velocity that particles spread
    /// evenly through a bin feel on average. Gauss-Legendre, 3 points on each of 16 equal
    /// parts of the interval.
    pub fn mean(&self, lo: f64, hi: f64) -> f64 {
        const PARTS: usize = 16;
        let nodes = [
            (-(0.6_f64).sqrt(), 5.0 / 9.0),
            (0.0, 8.0 / 9.0),
            ((0.6_f64).sqrt(), 5.0 / 9.0),
        ];
        let h = (hi - lo) / PARTS as f64;
        let mut sum = 0.0;
        for i in 0..PARTS {
            let centre = lo + (i as f64 + 0.5) * h;
            for (x, w) in nodes {
                sum += w * self.u(centre + 0.5 * h * x);
            }
        }
        sum / (2.0 * PARTS as f64)
    }

    /// Local shear rate `u'(y) = du/dy` (1/time) at any real `y`; `E_xy = E_yx = u'/2`
    /// (docs/physics.md section 2). A non-finite `y` gives NaN.
    pub fn du_dy(&self, y: f64) -> f64 {
        self.interpolate(y, 1)
    }

    /// Largest `|u|` over the table nodes (`a`/time).
    pub fn max_abs_u(&self) -> f64 {
        self.max_abs_u
    }

    /// Largest `|u'|` over the table nodes (1/time): the `gdot_max` of the Stokes number
    /// (docs/physics.md section 1).
    pub fn max_abs_shear_rate(&self) -> f64 {
        self.max_abs_shear_rate
    }

    /// The expression as given.
    pub fn expr(&self) -> &str {
        &self.expr
    }

    /// The period `L_y` (`a`).
    pub fn l_y(&self) -> f64 {
        self.l_y
    }

    /// `(u(y), u'(y))` with one table lookup: the simulator's per-particle call.
    #[inline]
    pub fn u_and_slope(&self, y: f64) -> (f64, f64) {
        let (i, t) = self.locate(y);
        let (a, b) = (&self.nodes[i], &self.nodes[i + 1]);
        let w = hermite_weights(t, self.spacing);
        (
            w[0] * a[0] + w[1] * a[1] + w[2] * b[0] + w[3] * b[1],
            w[0] * a[1] + w[1] * a[2] + w[2] * b[1] + w[3] * b[2],
        )
    }

    /// Table interval and fraction within it of any real `y` (positions inside the box
    /// skip the costly periodic reduction).
    #[inline]
    fn locate(&self, y: f64) -> (usize, f64) {
        let y = if (0.0..self.l_y).contains(&y) {
            y
        } else {
            y.rem_euclid(self.l_y)
        };
        let x = y / self.spacing;
        // `x` may round up to TABLE_INTERVALS; a NaN `x` casts to 0 and propagates via `t`.
        let i = (x as usize).min(TABLE_INTERVALS - 1);
        (i, x - i as f64)
    }

    /// Cubic Hermite interpolation of table column `k` (value) using column `k + 1` (slope).
    fn interpolate(&self, y: f64, k: usize) -> f64 {
        let (i, t) = self.locate(y);
        let (a, b) = (&self.nodes[i], &self.nodes[i + 1]);
        let w = hermite_weights(t, self.spacing);
        w[0] * a[k] + w[1] * a[k + 1] + w[2] * b[k] + w[3] * b[k + 1]
    }

    /// Compares the interpolated `u` and `u'` with the exact ones at every interval midpoint
    /// and refuses the worst offender, if any exceeds `TABLE_TOLERANCE`.
    fn check_resolution(&self, exact: &Exact) -> Result<(), String> {
        let scales = [self.max_abs_u, self.max_abs_shear_rate];
        // (error / allowed error, y, column)
        let mut worst = (0.0_f64, 0.0, 0);
        for i in 0..TABLE_INTERVALS {
            let y = (i as f64 + 0.5) * self.spacing;
            let truth = exact.at(y)?;
            for k in 0..2 {
                let error = (self.interpolate(y, k) - truth[k]).abs();
                let ratio = if error == 0.0 {
                    0.0
                } else {
                    error / (TABLE_TOLERANCE * scales[k])
                };
                if ratio > worst.0 {
                    worst = (ratio, y, k);
                }
            }
        }
        let (ratio, y, k) = worst;
        if ratio <= 1.0 {
            return Ok(());
        }
        let name = ["u", "u'"][k];
        Err(format!(
            "{name} varies too fast near y = {y:.4} to be tabulated (interpolation error \
             {:.3e} > {TABLE_TOLERANCE:e} of max |{name}| = {:.3e}); is it singular or not \
             smooth there?",
            ratio * TABLE_TOLERANCE * scales[k],
            scales[k]
        ))
    }

    /// Value and slope must agree at `y = 0` and `y = L_y` (docs/physics.md section 2).
    fn check_periodic(&self) -> Result<(), String> {
        let (start, end) = (&self.nodes[0], &self.nodes[TABLE_INTERVALS]);
        let scales = [self.max_abs_u, self.max_abs_shear_rate];
        for (k, name) in ["u", "u'"].into_iter().enumerate() {
            if (end[k] - start[k]).abs() > PERIODIC_TOLERANCE * scales[k] {
                return Err(format!(
                    "not periodic in L_y = {}: {name}(0) = {:.6e} but {name}(L_y) = {:.6e} \
                     (tolerance {PERIODIC_TOLERANCE:e} of max |{name}| = {:.3e})",
                    self.l_y, start[k], end[k], scales[k]
                ));
            }
        }
        Ok(())
    }
}

/// Direct evaluation of the expression and its first two y-derivatives; used only while
/// building and checking the table.
struct Exact {
    u: Expr,
    derivatives: Derivatives,
    /// Values of the expression's variables in exmex's (sorted) order, with `y` set to 0.
    variables: Vec<f64>,
    /// Position of `y` among the variables, if the expression uses it.
    y_slot: Option<usize>,
}

/// How `u'` and `u''` are obtained.
enum Derivatives {
    /// The expression does not depend on `y`: both vanish.
    Constant,
    /// exmex's symbolic first and second partial derivatives in `y` (boxed: exmex
    /// expressions are large).
    Symbolic(Box<[Expr; 2]>),
    /// 4th-order central differences of `u` with this step (`a`).
    FiniteDifference(f64),
}

impl Exact {
    fn parse(expr: &str, l_y: f64) -> Result<Exact, String> {
        check_function_names(expr)?;
        let u = Expr::parse(expr).map_err(|e| match locate_syntax_error(expr) {
            Some(place) => format!("does not parse {place}"),
            None => format!("does not parse: {e}"),
        })?;
        let names = u.var_names().to_vec();
        if let Some(unknown) = names
            .iter()
            .find(|n| !ALLOWED_VARIABLES.contains(&n.as_str()))
        {
            return Err(format!(
                "unknown symbol `{unknown}`: the profile may only use the variable y, the \
                 constants L (= L_y) and pi, numbers, and exmex's operators"
            ));
        }
        let variables = names
            .iter()
            .map(|n| match n.as_str() {
                "L" => l_y,
                "pi" => std::f64::consts::PI,
                _ => 0.0,
            })
            .collect();
        let y_slot = names.iter().position(|n| n == "y");
        let derivatives = match y_slot {
            None => Derivatives::Constant,
            Some(slot) => {
                let symbolic = u.clone().partial(slot).and_then(|du| {
                    let d2u = du.clone().partial(slot)?;
                    Ok((du, d2u))
                });
                match symbolic {
                    Ok((du, d2u)) => Derivatives::Symbolic(Box::new([du, d2u])),
                    Err(_) => Derivatives::FiniteDifference(FD_STEP * l_y),
                }
            }
        };
        Ok(Exact {
            u,
            derivatives,
            variables,
            y_slot,
        })
    }

    /// `[u, u', u'']` at `y`, refusing non-finite results.
    fn at(&self, y: f64) -> Result<[f64; 3], String> {
        let result = match &self.derivatives {
            Derivatives::Constant => [self.eval(&self.u, y)?, 0.0, 0.0],
            Derivatives::Symbolic(d) => [
                self.eval(&self.u, y)?,
                self.eval(&d[0], y)?,
                self.eval(&d[1], y)?,
            ],
            Derivatives::FiniteDifference(h) => {
                let f = |s: f64| self.eval(&self.u, y + s * h);
                let (m2, m1, c, p1, p2) = (f(-2.0)?, f(-1.0)?, f(0.0)?, f(1.0)?, f(2.0)?);
                [
                    c,
                    (m2 - 8.0 * m1 + 8.0 * p1 - p2) / (12.0 * h),
                    (-m2 + 16.0 * m1 - 30.0 * c + 16.0 * p1 - p2) / (12.0 * h * h),
                ]
            }
        };
        match result.iter().position(|v| !v.is_finite()) {
            None => Ok(result),
            Some(k) => Err(format!(
                "{} is not finite at y = {y}: {}",
                ["u", "u'", "u''"][k],
                result[k]
            )),
        }
    }

    fn eval(&self, f: &Expr, y: f64) -> Result<f64, String> {
        let mut variables = self.variables.clone();
        if let Some(slot) = self.y_slot {
            variables[slot] = y;
        }
        f.eval(&variables)
            .map_err(|e| format!("evaluation failed at y = {y}: {e}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Checks `u` and `u'` against closed forms at many `y`, including outside `[0, L)`.
    fn check(expr: &str, l: f64, u: impl Fn(f64) -> f64, du: impl Fn(f64) -> f64) {
        let p = FlowProfile::new(expr, l).unwrap();
        let n = 5000;
        for j in 0..=n {
            let y = -2.0 * l + 5.0 * l * j as f64 / n as f64;
            assert!(
                (p.u(y) - u(y)).abs() < 1e-9 * p.max_abs_u(),
                "{expr} u at {y}"
            );
            assert!(
                (p.du_dy(y) - du(y)).abs() < 1e-9 * p.max_abs_shear_rate(),
                "{expr} u' at {y}"
            );
            assert_eq!(p.u_and_slope(y), (p.u(y), p.du_dy(y)));
        }
    }

    #[test]
    fn sine_profile() {
        let (l, k) = (50.0, 2.0 * PI / 50.0);
        check(
            "0.1*sin(2*pi*y/L)",
            l,
            |y| 0.1 * (k * y).sin(),
            |y| 0.1 * k * (k * y).cos(),
        );
        let p = FlowProfile::new("0.1*sin(2*pi*y/L)", l).unwrap();
        assert!((p.max_abs_u() - 0.1).abs() < 1e-6);
        assert!((p.max_abs_shear_rate() - 0.1 * k).abs() < 1e-12);
        assert_eq!((p.expr(), p.l_y()), ("0.1*sin(2*pi*y/L)", 50.0));
    }

    #[test]
    fn sine_plus_cosine_profile() {
        let k = 2.0 * PI / 80.0;
        check(
            "0.1*sin(2*pi*y/L) + 0.2*cos(2*pi*y/L)",
            80.0,
            |y| 0.1 * (k * y).sin() + 0.2 * (k * y).cos(),
            |y| k * (0.1 * (k * y).cos() - 0.2 * (k * y).sin()),
        );
    }

    #[test]
    fn sine_cubed_profile() {
        let k = 2.0 * PI / 100.0;
        check(
            "0.1*sin(2*pi*y/L)^3",
            100.0,
            |y| 0.1 * (k * y).sin().powi(3),
            |y| 0.3 * k * (k * y).sin().powi(2) * (k * y).cos(),
        );
    }

    #[test]
    fn two_mode_profile() {
        let k = 2.0 * PI / 100.0;
        check(
            "0.05*sin(2*pi*2*y/L)^2 + 0.1*cos(2*pi*y/L)",
            100.0,
            |y| 0.05 * (2.0 * k * y).sin().powi(2) + 0.1 * (k * y).cos(),
            |y| 0.1 * k * (4.0 * k * y).sin() - 0.1 * k * (k * y).sin(),
        );
    }

    #[test]
    fn exmex_constants_and_finite_difference_fallback() {
        let k = 2.0 * PI / 50.0;
        check(
            "0.1*sin(2*PI*y/L)",
            50.0,
            |y| 0.1 * (k * y).sin(),
            |y| 0.1 * k * (k * y).cos(),
        );
        // exmex cannot differentiate `abs`: u' and u'' come from finite differences.
        check(
            "0.1*abs(sin(2*pi*y/L))^2",
            50.0,
            |y| 0.1 * (k * y).sin().powi(2),
            |y| 0.1 * k * (2.0 * k * y).sin(),
        );
    }

    #[test]
    fn e_notation_numbers() {
        let k = 2.0 * PI / 50.0;
        check(
            "1e-3*sin(2*pi*y/L) + 2.5E+1*0",
            50.0,
            |y| 1e-3 * (k * y).sin(),
            |y| 1e-3 * k * (k * y).cos(),
        );
        // Euler's number still reads as a constant next to a number.
        check(
            "2*e*cos(2*pi*y/L)",
            50.0,
            |y| 2.0 * std::f64::consts::E * (k * y).cos(),
            |y| -2.0 * std::f64::consts::E * k * (k * y).sin(),
        );
    }

    #[test]
    fn refuses_unknown_function_naming_the_known_ones() {
        let message = refusal("0.1*SIN(2*pi*y/L)", 50.0);
        assert!(
            message.contains("unknown function `SIN`") && message.contains("sin, cos"),
            "{message}"
        );
    }

    #[test]
    fn constant_profile_has_no_shear() {
        let p = FlowProfile::new("0.3", 20.0).unwrap();
        assert_eq!(
            (p.u(7.0), p.du_dy(-3.0), p.max_abs_shear_rate()),
            (0.3, 0.0, 0.0)
        );
    }

    #[test]
    fn interpolation_error_is_round_off() {
        let l = 50.0;
        let k = 2.0 * PI / l;
        let p = FlowProfile::new("0.1*sin(2*pi*y/L)", l).unwrap();
        let (mut err_u, mut err_du) = (0.0_f64, 0.0_f64);
        for j in 0..100_000 {
            let y = l * (j as f64 + 0.37) / 100_000.0;
            err_u = err_u.max((p.u(y) - 0.1 * (k * y).sin()).abs() / 0.1);
            err_du = err_du.max((p.du_dy(y) - 0.1 * k * (k * y).cos()).abs() / (0.1 * k));
        }
        assert!(err_u < 1e-12 && err_du < 1e-12, "{err_u:e} {err_du:e}");
    }

    #[test]
    fn wraps_periodically() {
        let p = FlowProfile::new("0.1*sin(2*pi*y/L)^3", 100.0).unwrap();
        for y in [0.0, 0.3, 17.25, 99.99] {
            for shift in [-300.0, -100.0, 100.0, 1e4] {
                assert!((p.u(y + shift) - p.u(y)).abs() < 1e-12);
                assert!((p.du_dy(y + shift) - p.du_dy(y)).abs() < 1e-12);
            }
        }
        assert_eq!(p.u(100.0), p.u(0.0));
        assert!(p.u(f64::NAN).is_nan() && p.du_dy(f64::INFINITY).is_nan());
    }

    fn refusal(expr: &str, l: f64) -> String {
        FlowProfile::new(expr, l).unwrap_err().to_string()
    }

    #[test]
    fn bin_means_are_the_integrals_over_the_bins() {
        // 0.1 sin(2 pi y / L): the mean over [lo, hi] is 0.1 L (cos k lo - cos k hi) / (2 pi w).
        let l = 50.0;
        let p = FlowProfile::new("0.1*sin(2*pi*y/L)", l).unwrap();
        let k = 2.0 * std::f64::consts::PI / l;
        for (lo, hi) in [(0.0, 2.0), (11.0, 13.0), (24.0, 26.0), (48.0, 52.0)] {
            let exact = 0.1 * ((k * lo).cos() - (k * hi).cos()) / (k * (hi - lo));
            assert!(
                (p.mean(lo, hi) - exact).abs() < 1e-9,
                "{lo}-{hi}: {} {exact}",
                p.mean(lo, hi)
            );
        }
        // Across the sharp band of a flat-topped profile the bin mean is well below the
        // centre value (0.0729 against 0.0638 in the first bin of datasets/plugs.csv's plugs_000).
        let p = FlowProfile::new("0.1*tanh(3*sin(8*pi*y/L))", 80.0).unwrap();
        let fine = (0..20000)
            .map(|i| p.u(2.0 * (i as f64 + 0.5) / 20000.0))
            .sum::<f64>()
            / 20000.0;
        assert!(
            (p.mean(0.0, 2.0) - fine).abs() < 1e-7,
            "{} {fine}",
            p.mean(0.0, 2.0)
        );
        assert!((p.u(1.0) - 0.0729).abs() < 1e-4 && (fine - 0.0638).abs() < 1e-4);
    }

    #[test]
    fn refuses_non_periodic() {
        assert!(refusal("0.1*y/L", 50.0).contains("not periodic"));
        // Same value at 0 and L, opposite slope.
        let message = refusal("sin(2*pi*y/(2*L))", 50.0);
        assert!(
            message.contains("not periodic") && message.contains("u'(0)"),
            "{message}"
        );
    }

    #[test]
    fn refuses_unknown_symbol() {
        let message = refusal("k*sin(2*pi*y/L)", 50.0);
        assert!(message.contains("unknown symbol `k`"), "{message}");
        assert!(refusal("0.1*sin(2*pi*x/L)", 50.0).contains("unknown symbol `x`"));
    }

    #[test]
    fn refuses_garbage() {
        // A quote or a newline can never reach the quoted `profile` cell of a CSV file.
        for expr in [
            "",
            "0.1*sin(",
            "0.1*",
            "sin(2*pi*y/L))",
            "0.1 $ y",
            "y y",
            "0.1\"*y",
            "0.1*\nsin(2*pi*y/L)",
        ] {
            let message = refusal(expr, 50.0);
            assert!(message.contains(&format!("`{expr}`")), "{message}");
        }
    }

    #[test]
    fn refuses_singular() {
        // Pole between table nodes: caught by the resolution check, naming where.
        let message = refusal("1/(y-10)", 50.0);
        assert!(
            message.contains("near y = 10.0") && message.contains("singular"),
            "{message}"
        );
        // Pole on a table node.
        assert!(refusal("1/(y-25)", 50.0).contains("not finite at y = 25"));
        assert!(refusal("sqrt(y - 1)", 50.0).contains("not finite"));
    }

    #[test]
    fn refuses_bad_box() {
        for l in [0.0, -5.0, f64::NAN, f64::INFINITY] {
            assert!(refusal("0.1*sin(2*pi*y/L)", l).contains("L_y"));
        }
    }
}
