use super::*;

#[test]
fn probe() {
    for n in [2.1, 2.5, 3.0, 4.0, 8.0] {
        let t = std::time::Instant::now();
        let p = UnitProfile::compute(n).unwrap();
        let q = solve(n, p.period * 2, 16);
        let mut d = 0.0_f64;
        for k in -40..=40 {
            let x = k as f64 * 0.25;
            d = d
                .max((p.s_at(x) - q.s_at(x)).abs())
                .max((p.w_at(x) - q.w_at(x)).abs());
        }
        let (a, b) = p.virial_integrals();
        eprintln!(
            "n {n}: period {} it {} res {:e} adres {:e} {:e} support {} smax {} wmax {} virial {:e} kappa {} diff {:e} t {:?}",
            p.period, p.iterations, p.residual, p.advance_delay_residual(),q.advance_delay_residual(), p.support, p.s[0], p.w_at(0.5), (a-b)/a, p.energy_constant(), d, t.elapsed()
        );
    }
}
