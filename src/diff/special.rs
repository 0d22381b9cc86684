//! Polygamma functions for the dispersion prior ([`super::dispersion`]) and the moderated
//! t-test's prior ([`super::moderated`]): trigamma `ψ₁`, tetragamma `ψ₂` and the inverse of
//! trigamma (limma's `trigammaInverse`). The digamma function is statrs'.

/// The trigamma function `ψ₁(x)` for `x > 0`: the recurrence `ψ₁(x) = ψ₁(x+1) + 1/x²` up to
/// `x >= 20`, then its asymptotic series.
pub fn trigamma(x: f64) -> f64 {
    let (mut x, mut sum) = (x, 0.0);
    while x < 20.0 {
        sum += 1.0 / (x * x);
        x += 1.0;
    }
    let inverse = 1.0 / x;
    let i2 = inverse * inverse;
    // 1/x + 1/(2x²) + Σ B₂ₖ / x^(2k+1)
    let series = inverse
        * (1.0
            + inverse / 2.0
            + i2 * (1.0 / 6.0
                + i2 * (-1.0 / 30.0 + i2 * (1.0 / 42.0 + i2 * (-1.0 / 30.0 + i2 * 5.0 / 66.0)))));
    sum + series
}

/// The tetragamma function `ψ₂(x)` for `x > 0`: the recurrence `ψ₂(x) = ψ₂(x+1) - 2/x³` up to
/// `x >= 20`, then the derivative of trigamma's series.
pub fn tetragamma(x: f64) -> f64 {
    let (mut x, mut sum) = (x, 0.0);
    while x < 20.0 {
        sum -= 2.0 / (x * x * x);
        x += 1.0;
    }
    let inverse = 1.0 / x;
    let i2 = inverse * inverse;
    // -1/x² - 1/x³ - 1/(2x⁴) + 1/(6x⁶) - 1/(6x⁸) + 3/(10x¹⁰) - 5/(6x¹²)
    let series = -i2
        * (1.0
            + inverse
            + i2 * (0.5 + i2 * (-1.0 / 6.0 + i2 * (1.0 / 6.0 + i2 * (-0.3 + i2 * 5.0 / 6.0)))));
    sum + series
}

/// The `y > 0` with `ψ₁(y) = x`, for `x > 0`: limma's `trigammaInverse` (Newton's method on
/// `1/ψ₁` from `y = 1/2 + 1/x`, until the relative step is under 1e-8, at most 50 steps; `1/√x`
/// above 1e7 and `1/x` under 1e-6, where those are exact to double precision).
pub fn trigamma_inverse(x: f64) -> f64 {
    if x > 1e7 {
        return 1.0 / x.sqrt();
    }
    if x < 1e-6 {
        return 1.0 / x;
    }
    let mut y = 0.5 + 1.0 / x;
    for _ in 0..50 {
        let tri = trigamma(y);
        let step = tri * (1.0 - tri / x) / tetragamma(y);
        y += step;
        if -step / y < 1e-8 {
            break;
        }
    }
    y
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// ζ(3), Apéry's constant.
    const ZETA3: f64 = 1.202_056_903_159_594_2;

    #[test]
    fn trigamma_equals_its_closed_forms() {
        for (x, want) in [
            (1.0, PI * PI / 6.0),
            (0.5, PI * PI / 2.0),
            (1.5, PI * PI / 2.0 - 4.0),
            (2.0, PI * PI / 6.0 - 1.0),
            (4.0, PI * PI / 6.0 - 1.0 - 0.25 - 1.0 / 9.0),
        ] {
            assert!((trigamma(x) - want).abs() < 1e-14 * want, "{x}");
        }
    }

    #[test]
    fn tetragamma_equals_its_closed_forms_and_trigammas_slope() {
        // ψ₂(1) = -2ζ(3), ψ₂(1/2) = -14ζ(3), ψ₂(3) = ψ₂(1) + 2 + 2/8
        for (x, want) in [
            (1.0, -2.0 * ZETA3),
            (0.5, -14.0 * ZETA3),
            (3.0, -2.0 * ZETA3 + 2.0 + 0.25),
        ] {
            assert!((tetragamma(x) - want).abs() < 1e-13 * want.abs(), "{x}");
        }
        for x in [0.3, 2.7, 19.5, 45.0, 300.0] {
            let h = 1e-4 * x;
            let numeric = (trigamma(x + h) - trigamma(x - h)) / (2.0 * h);
            assert!(
                (tetragamma(x) - numeric).abs() < 1e-7 * numeric.abs(),
                "{x}"
            );
        }
    }

    #[test]
    fn trigamma_inverse_inverts_trigamma() {
        for y in [1e-3, 0.2, 1.0, 3.5, 40.0, 2_000.0] {
            let x = trigamma(y);
            let back = trigamma_inverse(x);
            assert!((back - y).abs() < 1e-7 * y, "{y} -> {x} -> {back}");
        }
    }
}
