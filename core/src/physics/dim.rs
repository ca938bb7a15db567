//! One source for 2D and 3D: the `Dim` trait with marker types `D2` (glam `Vec2`, `Mat2`)
//! and `D3` (`Vec3A`, `Mat3A`). The scene's `dimension` picks one, once, at start-up.

use glam::{Mat2, Mat3A, Vec2, Vec3A};
use std::fmt::Debug;
use std::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

/// A spatial dimension: its vector and (velocity-gradient / stress) tensor types.
pub trait Dim: Copy + Send + Sync + Debug + 'static {
    /// 2 or 3.
    const D: usize;
    /// Position, velocity, acceleration.
    type V: Copy
        + Default
        + Debug
        + PartialEq
        + Send
        + Sync
        + Add<Output = Self::V>
        + Sub<Output = Self::V>
        + Mul<f32, Output = Self::V>
        + Neg<Output = Self::V>
        + AddAssign
        + SubAssign
        + serde::Serialize
        + serde::de::DeserializeOwned;
    /// A D x D tensor (velocity gradient, deviatoric stress, its rate). Note that glam's
    /// `Default` for matrices is the identity: use `zero()`.
    type M: Copy
        + Debug
        + PartialEq
        + Send
        + Sync
        + Add<Output = Self::M>
        + Sub<Output = Self::M>
        + Mul<f32, Output = Self::M>
        + Mul<Self::M, Output = Self::M>
        + AddAssign
        + serde::Serialize
        + serde::de::DeserializeOwned;

    fn dot(a: Self::V, b: Self::V) -> f32;
    fn comp(v: Self::V, axis: usize) -> f32;
    fn set_comp(v: &mut Self::V, axis: usize, x: f32);
    /// The first D components of a 3-vector.
    fn from3(a: [f32; 3]) -> Self::V;
    /// The vector padded with zeros to 3 components.
    fn to3(v: Self::V) -> [f32; 3];

    /// The outer product a b^T: (a b^T)^{ab} = a^a b^b.
    fn outer(a: Self::V, b: Self::V) -> Self::M;
    /// Tensor times vector: (M v)^a = M^{ab} v^b.
    fn mat_vec(m: Self::M, v: Self::V) -> Self::V;
    fn transpose(m: Self::M) -> Self::M;
    fn trace(m: Self::M) -> f32;
    fn determinant(m: Self::M) -> f32;
    fn inverse(m: Self::M) -> Self::M;
    fn identity() -> Self::M;
    fn zero() -> Self::M;
    /// Component M^{ab} (row a, column b).
    fn entry(m: Self::M, a: usize, b: usize) -> f32;
    /// A symmetric tensor from its six components (xx, yy, zz, xy, xz, yz); the ones
    /// beyond D are ignored.
    fn sym_from6(s: [f32; 6]) -> Self::M;
    /// The six symmetric components (xx, yy, zz, xy, xz, yz), zeros beyond D.
    fn sym_to6(m: Self::M) -> [f32; 6];

    fn length2(v: Self::V) -> f32 {
        Self::dot(v, v)
    }
}

/// Two dimensions: the scene is solved in the x-y plane.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct D2;
/// Three dimensions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct D3;

impl Dim for D2 {
    const D: usize = 2;
    type V = Vec2;
    type M = Mat2;
    #[inline]
    fn dot(a: Vec2, b: Vec2) -> f32 {
        a.dot(b)
    }
    #[inline]
    fn comp(v: Vec2, axis: usize) -> f32 {
        v[axis]
    }
    #[inline]
    fn set_comp(v: &mut Vec2, axis: usize, x: f32) {
        v[axis] = x;
    }
    #[inline]
    fn from3(a: [f32; 3]) -> Vec2 {
        Vec2::new(a[0], a[1])
    }
    #[inline]
    fn to3(v: Vec2) -> [f32; 3] {
        [v.x, v.y, 0.0]
    }
    #[inline]
    fn outer(a: Vec2, b: Vec2) -> Mat2 {
        Mat2::from_cols(a * b.x, a * b.y)
    }
    #[inline]
    fn mat_vec(m: Mat2, v: Vec2) -> Vec2 {
        m * v
    }
    #[inline]
    fn transpose(m: Mat2) -> Mat2 {
        m.transpose()
    }
    #[inline]
    fn trace(m: Mat2) -> f32 {
        m.x_axis.x + m.y_axis.y
    }
    #[inline]
    fn determinant(m: Mat2) -> f32 {
        m.determinant()
    }
    #[inline]
    fn inverse(m: Mat2) -> Mat2 {
        m.inverse()
    }
    #[inline]
    fn identity() -> Mat2 {
        Mat2::IDENTITY
    }
    #[inline]
    fn zero() -> Mat2 {
        Mat2::ZERO
    }
    #[inline]
    fn entry(m: Mat2, a: usize, b: usize) -> f32 {
        m.col(b)[a]
    }
    fn sym_from6(s: [f32; 6]) -> Mat2 {
        Mat2::from_cols(Vec2::new(s[0], s[3]), Vec2::new(s[3], s[1]))
    }
    fn sym_to6(m: Mat2) -> [f32; 6] {
        [
            m.x_axis.x,
            m.y_axis.y,
            0.0,
            0.5 * (m.y_axis.x + m.x_axis.y),
            0.0,
            0.0,
        ]
    }
}

impl Dim for D3 {
    const D: usize = 3;
    type V = Vec3A;
    type M = Mat3A;
    #[inline]
    fn dot(a: Vec3A, b: Vec3A) -> f32 {
        a.dot(b)
    }
    #[inline]
    fn comp(v: Vec3A, axis: usize) -> f32 {
        v[axis]
    }
    #[inline]
    fn set_comp(v: &mut Vec3A, axis: usize, x: f32) {
        v[axis] = x;
    }
    #[inline]
    fn from3(a: [f32; 3]) -> Vec3A {
        Vec3A::from_array(a)
    }
    #[inline]
    fn to3(v: Vec3A) -> [f32; 3] {
        v.to_array()
    }
    #[inline]
    fn outer(a: Vec3A, b: Vec3A) -> Mat3A {
        Mat3A::from_cols(a * b.x, a * b.y, a * b.z)
    }
    #[inline]
    fn mat_vec(m: Mat3A, v: Vec3A) -> Vec3A {
        m * v
    }
    #[inline]
    fn transpose(m: Mat3A) -> Mat3A {
        m.transpose()
    }
    #[inline]
    fn trace(m: Mat3A) -> f32 {
        m.x_axis.x + m.y_axis.y + m.z_axis.z
    }
    #[inline]
    fn determinant(m: Mat3A) -> f32 {
        m.determinant()
    }
    #[inline]
    fn inverse(m: Mat3A) -> Mat3A {
        m.inverse()
    }
    #[inline]
    fn identity() -> Mat3A {
        Mat3A::IDENTITY
    }
    #[inline]
    fn zero() -> Mat3A {
        Mat3A::ZERO
    }
    #[inline]
    fn entry(m: Mat3A, a: usize, b: usize) -> f32 {
        m.col(b)[a]
    }
    fn sym_from6(s: [f32; 6]) -> Mat3A {
        Mat3A::from_cols(
            Vec3A::new(s[0], s[3], s[4]),
            Vec3A::new(s[3], s[1], s[5]),
            Vec3A::new(s[4], s[5], s[2]),
        )
    }
    fn sym_to6(m: Mat3A) -> [f32; 6] {
        let e = |a, b| 0.5 * (Self::entry(m, a, b) + Self::entry(m, b, a));
        [e(0, 0), e(1, 1), e(2, 2), e(0, 1), e(0, 2), e(1, 2)]
    }
}
