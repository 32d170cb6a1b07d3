//! The interactive desktop viewer of cadre (being written).
