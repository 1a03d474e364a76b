//! Every row against independent values: the jets' three derivatives against central differences
//! of the row's own value and derivatives, and the tangent rule against the first derivative.

use super::*;

/// Points inside each function's domain, away from kinks.
fn points(f: Fun) -> [f64; 3] {
    match f {
        Fun::Acosh => [1.3, 2.0, 3.5],
        Fun::Asin | Fun::Acos | Fun::Atanh => [-0.6, 0.1, 0.7],
        Fun::Sqrt | Fun::Ln | Fun::Log10 | Fun::Log2 | Fun::Cbrt => [0.4, 1.7, 3.0],
        Fun::Ln1p => [-0.5, 0.3, 2.0],
        _ => [-1.2, 0.3, 0.9],
    }
}

/// The derivatives of `f` at x (the jets' row).
fn derivs(f: Fun, x: f64) -> [f64; 3] {
    macro_rules! by_name {
        ($( $(#[$meta:meta])* $variant:ident $method:ident $unicode:literal $latex:literal
            real = $real:ident jets = $jets:ident
            tangent($x:ident, $y:ident, $dx:ident, $k:ident) = $tangent:expr;
            jets($jx:ident, $jy:ident) = $jet:expr; )*) => {
            match f {
                $(Fun::$variant => jets::$method(x, f.eval(x)),)*
            }
        };
    }
    with_functions!(by_name)
}

/// Central difference of g at x, step h, relative error ≈ h² (g‴ / 6) + ε/h.
fn central(g: impl Fn(f64) -> f64, x: f64, h: f64) -> f64 {
    (g(x + h) - g(x - h)) / (2.0 * h)
}

#[test]
fn jets_rows_are_the_derivatives_of_the_value() {
    // h = 1e-5: truncation ~1e-10 · |g‴|, rounding ~1e-16/1e-5 = 1e-11 relative to |g|.
    let h = 1e-5;
    for row in TABLE {
        let f = row.fun;
        for x in points(f) {
            let d = derivs(f, x);
            let fd1 = central(|u| f.eval(u), x, h);
            let fd2 = central(|u| derivs(f, u)[0], x, h);
            let fd3 = central(|u| derivs(f, u)[1], x, h);
            for (k, (got, want)) in d.iter().zip([fd1, fd2, fd3]).enumerate() {
                let tol = 1e-7 * (1.0 + want.abs());
                assert!(
                    (got - want).abs() <= tol,
                    "{:?} at {x}: derivative {} is {got}, finite differences {want}",
                    f,
                    k + 1
                );
            }
        }
    }
}

#[test]
fn tangent_rule_is_the_first_derivative() {
    for row in TABLE {
        let f = row.fun;
        for x in points(f) {
            let y = f.eval(x);
            let t = tangent(f, x, y, 1.0, &|c| c);
            let d1 = derivs(f, x)[0];
            assert!(
                (t - d1).abs() <= 1e-14 * (1.0 + d1.abs()),
                "{f:?} at {x}: the tangent rule gives {t}, the jets' row {d1}"
            );
            // Linear in dx.
            assert!((tangent(f, x, y, 3.0, &|c| c) - 3.0 * t).abs() <= 1e-13 * (1.0 + t.abs()));
        }
    }
}

#[test]
fn methods_name_their_rows() {
    for (i, row) in TABLE.iter().enumerate() {
        assert_eq!(row.fun as usize, i);
        assert_eq!(row.fun.row().method, row.method);
        if row.method.is_empty() {
            assert_eq!(row.fun, Fun::Step);
        } else {
            assert_eq!(Fun::from_method(row.method), Some(row.fun));
        }
    }
    assert_eq!(Fun::from_method(""), None);
    assert_eq!(Fun::from_method("step"), None);
    assert_eq!(Fun::Step.eval(-0.0), 1.0);
    assert_eq!(Fun::Step.eval(f64::NAN), 0.0);
}
