use qscalar::{Quat, Scalar};
use qsparse::{SparseCholesky, TripletMatrix};

fn lcg(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

#[test]
fn grid_connection_laplacian_solves() {
    for &side in &[1usize, 2, 5, 30, 80] {
        let n = side * side;
        let mut t = TripletMatrix::<Quat<f64>>::new(n, n);
        let mut st = 7u64;
        let mut diag = vec![0.5; n];
        for r in 0..side {
            for c in 0..side {
                let i = r * side + c;
                for (dr, dc) in [(0, 1), (1, 0)] {
                    if r + dr < side && c + dc < side {
                        let j = (r + dr) * side + c + dc;
                        let q = Quat::new(lcg(&mut st), lcg(&mut st), lcg(&mut st), lcg(&mut st))
                            .normalize();
                        t.push(i, j, -q).unwrap();
                        t.push(j, i, -q.conj()).unwrap();
                        diag[i] += 1.0;
                        diag[j] += 1.0;
                    }
                }
            }
        }
        for i in 0..n {
            t.push(i, i, Quat::from_real(diag[i])).unwrap();
        }
        let a = t.to_csc();
        let chol = SparseCholesky::factorize(&a).unwrap();
        let b: Vec<Quat<f64>> = (0..n)
            .map(|_| Quat::new(lcg(&mut st), lcg(&mut st), lcg(&mut st), lcg(&mut st)))
            .collect();
        let x = chol.solve(&b).unwrap();
        let mut ax = vec![Quat::default(); n];
        a.mul_vec(&x, &mut ax).unwrap();
        let res: f64 = ax
            .iter()
            .zip(&b)
            .map(|(p, q)| (*p - *q).abs2())
            .sum::<f64>()
            .sqrt();
        let bn: f64 = b.iter().map(|q| q.abs2()).sum::<f64>().sqrt();
        println!(
            "side {side}: rel residual {:e} stats {:?}",
            res / bn,
            chol.stats()
        );
        assert!(res / bn < 1e-12, "residual {}", res / bn);
    }
}
