//! B-spline evaluation: basis functions and their derivatives, and the rational (NURBS)
//! derivatives of curves and surfaces computed from them.

pub mod basis;
mod curve;
mod surface;
