//! STEP (ISO 10303-21) reading for cadre.
//!
//! Two layers: [`syntax`] reads the exchange structure (lexer, HEADER, an index of DATA
//! instances decoded on demand), and [`map`] turns the B-Rep, assembly and presentation
//! content of AP203, AP214 and AP242 into a [`cadre_brep::Model`].

pub mod map;
pub mod syntax;

pub use map::map_file;
