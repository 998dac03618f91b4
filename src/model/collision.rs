//! The head-on collision of two beads through one power-law contact `V = a δⁿ`, reduced mass
//! `μ`, relative speed `w` (paper eq. 6 for a single contact; energy integral
//! `½ μ δ̇² + a δⁿ = ½ μ w²`): it is elastic, reaches the peak overlap
//! `δ_max = (μ w²/(2a))^{1/n}` and lasts `t_c = (2 δ_max / w) · √π Γ(1+1/n) / Γ(1/2+1/n)`
//! (the integral `∫₀¹ dx/√(1−xⁿ)`; `π δ_max/w` for `n = 2`). Used by the plausibility warnings
//! of physical scenes.

/// Γ(x) for x ≥ 0.5 (Lanczos, g = 7, 9 terms: relative error below 1e-14 there).
pub fn gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    let x = x - 1.0;
    let t = x + G + 0.5;
    let sum = C[1..]
        .iter()
        .enumerate()
        .fold(C[0], |s, (i, c)| s + c / (x + i as f64 + 1.0));
    (2.0 * std::f64::consts::PI).sqrt() * t.powf(x + 0.5) * (-t).exp() * sum
}

/// Peak overlap `δ_max` and duration `t_c` of a head-on collision of two beads of reduced mass
/// `mu` at relative speed `w > 0` through the contact `V = a δⁿ` (module docs).
pub fn collision(mu: f64, w: f64, n: f64, a: f64) -> (f64, f64) {
    let d = (mu * w * w / (2.0 * a)).powf(1.0 / n);
    let shape = std::f64::consts::PI.sqrt() * gamma(1.0 + 1.0 / n) / gamma(0.5 + 1.0 / n);
    (d, 2.0 * d / w * shape)
}
