//! Property tests of the quaternion algebra, the block homomorphisms, and agreement with two
//! independent quaternion implementations (quaternion-core and num-quaternion).

use num_complex::Complex;
use proptest::prelude::*;
use qscalar::blocks::{complex_adjoint, left_block, mat4_mul, right_block};
use qscalar::strategies::{complex, nonzero_quat, quat, unit_quat};
use qscalar::{Quat, Scalar};

type Q = Quat<f64>;

fn close(a: Q, b: Q, tol: f64) -> bool {
    (a - b).norm() <= tol * (1.0 + a.norm().max(b.norm()))
}

fn close_mat4(a: &[[f64; 4]; 4], b: &[[f64; 4]; 4], tol: f64) -> bool {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .all(|(x, y)| (x - y).abs() <= tol)
}

fn transpose4(a: &[[f64; 4]; 4]) -> [[f64; 4]; 4] {
    let mut t = [[0.0; 4]; 4];
    for i in 0..4 {
        for j in 0..4 {
            t[i][j] = a[j][i];
        }
    }
    t
}

fn cmul2(a: &[[Complex<f64>; 2]; 2], b: &[[Complex<f64>; 2]; 2]) -> [[Complex<f64>; 2]; 2] {
    let mut c = [[Complex::new(0.0, 0.0); 2]; 2];
    for i in 0..2 {
        for j in 0..2 {
            c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j];
        }
    }
    c
}

#[test]
fn hamilton_rules() {
    let (one, i, j, k) = (Q::from_real(1.0), Q::i(), Q::j(), Q::k());
    assert_eq!(i * i, -one);
    assert_eq!(j * j, -one);
    assert_eq!(k * k, -one);
    assert_eq!(i * j * k, -one);
    assert_eq!(i * j, k);
    assert_eq!(j * k, i);
    assert_eq!(k * i, j);
}

#[test]
fn noncommutativity_witness() {
    assert_ne!(Q::i() * Q::j(), Q::j() * Q::i());
    const { assert!(!<Q as Scalar>::IS_COMMUTATIVE) };
}

#[test]
fn imaginary_product_is_minus_dot_plus_cross() {
    // For imaginary a, b: ab = −a·b + a×b (docs/MATH.md, "Quaternions and quaternionic
    // vectors").
    let a = [1.0, 2.0, 3.0];
    let b = [-2.0, 0.5, 4.0];
    let p = Q::from_vector(a) * Q::from_vector(b);
    let dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let cross = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    assert_eq!(p, Q::new(-dot, cross[0], cross[1], cross[2]));
}

#[test]
fn rotation_by_quarter_turn_about_z() {
    let half = std::f64::consts::FRAC_PI_4;
    let r = Q::new(half.cos(), 0.0, 0.0, half.sin());
    let v = r.rotate_vector([1.0, 0.0, 0.0]);
    assert!((v[0]).abs() < 1e-15 && (v[1] - 1.0).abs() < 1e-15 && v[2].abs() < 1e-15);
}

proptest! {
    #[test]
    fn associativity(p in quat(3.0), q in quat(3.0), r in quat(3.0)) {
        prop_assert!(close((p * q) * r, p * (q * r), 1e-13));
    }

    #[test]
    fn distributivity(p in quat(3.0), q in quat(3.0), r in quat(3.0)) {
        prop_assert!(close(p * (q + r), p * q + p * r, 1e-13));
        prop_assert!(close((q + r) * p, q * p + r * p, 1e-13));
    }

    #[test]
    fn conjugate_reverses_products(p in quat(3.0), q in quat(3.0)) {
        prop_assert!(close((p * q).conj(), q.conj() * p.conj(), 1e-14));
    }

    #[test]
    fn norm_is_multiplicative(p in quat(3.0), q in quat(3.0)) {
        prop_assert!(((p * q).norm() - p.norm() * q.norm()).abs() <= 1e-13 * (1.0 + p.norm() * q.norm()));
    }

    #[test]
    fn inverse_is_two_sided(q in nonzero_quat(3.0, 1e-3)) {
        prop_assert!(close(q * q.inv(), Q::from_real(1.0), 1e-12));
        prop_assert!(close(q.inv() * q, Q::from_real(1.0), 1e-12));
    }

    #[test]
    fn divisions_solve_their_equations(p in quat(3.0), q in nonzero_quat(3.0, 1e-2)) {
        prop_assert!(close(p.right_div(q) * q, p, 1e-12));
        prop_assert!(close(q * p.left_div(q), p, 1e-12));
    }

    #[test]
    fn exp_inverts_ln(q in nonzero_quat(2.0, 1e-2)) {
        prop_assert!(close(q.ln().exp(), q, 1e-12));
    }

    #[test]
    fn powf_matches_repeated_product(q in nonzero_quat(2.0, 1e-2)) {
        prop_assert!(close(q.powf(3.0), q * q * q, 1e-11));
    }

    #[test]
    fn unit_rotation_preserves_length(r in unit_quat(), v in prop::array::uniform3(-5.0..5.0f64)) {
        let w = r.rotate_vector(v);
        let n = |a: [f64; 3]| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        prop_assert!((n(w) - n(v)).abs() <= 1e-12 * (1.0 + n(v)));
    }

    #[test]
    fn left_block_is_homomorphism(p in quat(3.0), q in quat(3.0)) {
        prop_assert!(close_mat4(&left_block(p * q), &mat4_mul(&left_block(p), &left_block(q)), 1e-12));
        prop_assert!(close_mat4(&left_block(p.conj()), &transpose4(&left_block(p)), 0.0));
    }

    #[test]
    fn blocks_act_as_products(p in quat(3.0), q in quat(3.0)) {
        // L(p) vec(q) = vec(pq) and R(q) vec(p) = vec(pq).
        let apply = |m: [[f64; 4]; 4], v: Q| {
            let v = v.to_array();
            Q::from_array(std::array::from_fn(|i| (0..4).map(|k| m[i][k] * v[k]).sum()))
        };
        prop_assert!(close(apply(left_block(p), q), p * q, 1e-13));
        prop_assert!(close(apply(right_block(q), p), p * q, 1e-13));
    }

    #[test]
    fn left_and_right_blocks_commute(p in quat(3.0), q in quat(3.0)) {
        let (l, r) = (left_block(p), right_block(q));
        prop_assert!(close_mat4(&mat4_mul(&l, &r), &mat4_mul(&r, &l), 1e-12));
        // Right blocks are an anti-homomorphism: R(pq) = R(q) R(p).
        prop_assert!(close_mat4(&right_block(p * q), &mat4_mul(&right_block(q), &right_block(p)), 1e-12));
    }

    #[test]
    fn complex_adjoint_is_homomorphism(p in quat(3.0), q in quat(3.0)) {
        let lhs = complex_adjoint(p * q);
        let rhs = cmul2(&complex_adjoint(p), &complex_adjoint(q));
        for i in 0..2 {
            for j in 0..2 {
                prop_assert!((lhs[i][j] - rhs[i][j]).norm() <= 1e-12);
            }
        }
        // χ(q̄) = χ(q)ᴴ.
        let (c, h) = (complex_adjoint(p.conj()), complex_adjoint(p));
        for i in 0..2 {
            for j in 0..2 {
                prop_assert_eq!(c[i][j], h[j][i].conj());
            }
        }
    }

    #[test]
    fn complex_pair_round_trips(z1 in complex(3.0), z2 in complex(3.0)) {
        let q = Q::from_complex_pair(z1, z2);
        prop_assert_eq!(q.to_complex_pair(), (z1, z2));
        // z1 + z2 j with complex numbers read as w + x i.
        let j = Q::j();
        let as_q = |z: Complex<f64>| Q::new(z.re, z.im, 0.0, 0.0);
        prop_assert!(close(as_q(z1) + as_q(z2) * j, q, 1e-15));
    }

    #[test]
    fn scalar_trait_blocks_match_free_functions(q in quat(3.0)) {
        let mut out = [0.0; 16];
        q.real_block(&mut out);
        let b = left_block(q);
        prop_assert!(out.chunks(4).zip(b.iter()).all(|(r, s)| r == s));
        let mut col = [Complex::new(0.0, 0.0); 2];
        q.to_complex_column(&mut col);
        prop_assert_eq!(<Q as Scalar>::from_complex_column(&col), q);
    }

    #[test]
    fn agrees_with_quaternion_core(p in quat(1.5), q in nonzero_quat(3.0, 1e-2)) {
        let (pc, qc): (quaternion_core::Quaternion<f64>, _) = (p.into(), q.into());
        prop_assert!(close(quaternion_core::mul(pc, qc).into(), p * q, 1e-13));
        prop_assert!(close(quaternion_core::inv(qc).into(), q.inv(), 1e-12));
        prop_assert!(close(quaternion_core::conj(pc).into(), p.conj(), 0.0));
        prop_assert!((quaternion_core::norm(pc) - p.norm()).abs() < 1e-13);
        prop_assert!(close(quaternion_core::exp(pc).into(), p.exp(), 1e-12));
        // quaternion-core's ln and pow use atan(|v|/w): the principal branch only for w > 0.
        if q.w > 0.1 {
            prop_assert!(close(quaternion_core::ln(qc).into(), q.ln(), 1e-12));
            prop_assert!(close(quaternion_core::pow(qc, 2.5).into(), q.powf(2.5), 1e-11));
        }
    }

    #[test]
    fn agrees_with_num_quaternion(p in quat(3.0), q in nonzero_quat(2.0, 1e-2)) {
        use num_quaternion::Quaternion;
        let to_nq = |a: Q| Quaternion::new(a.w, a.x, a.y, a.z);
        let from_nq = |a: Quaternion<f64>| Q::new(a.w, a.x, a.y, a.z);
        prop_assert!(close(from_nq(to_nq(p) * to_nq(q)), p * q, 1e-13));
        prop_assert!(close(from_nq(to_nq(q).exp()), q.exp(), 1e-12));
        prop_assert!(close(from_nq(to_nq(q).ln()), q.ln(), 1e-12));
    }

    #[test]
    fn as_reals_is_the_interleaved_layout(v in prop::collection::vec(quat(2.0), 0..8)) {
        let reals = Q::as_reals(&v);
        prop_assert_eq!(reals.len(), 4 * v.len());
        for (q, chunk) in v.iter().zip(reals.chunks(4)) {
            prop_assert_eq!(chunk, &q.to_array()[..]);
        }
    }
}
