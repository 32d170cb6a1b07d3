//! One module per subcommand.

pub mod bench;
pub mod info;
pub mod mesh;
pub mod render;
pub mod toolpath;
pub mod verify;
pub mod view;
