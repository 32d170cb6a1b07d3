//! Boundary-representation model for cadre (being written).
