//! Typed indices into the [`crate::Model`] arenas. A `u32` each: models stay compact and an id
//! of one kind can never index another arena.

macro_rules! id_type {
    ($(#[$doc:meta] $name:ident),* $(,)?) => {$(
        #[$doc]
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub struct $name(pub u32);

        impl $name {
            /// The arena index.
            pub fn index(self) -> usize {
                self.0 as usize
            }
        }
    )*};
}

id_type!(
    /// Index of a [`cadre_geom::Surface`] in [`crate::Model::surfaces`].
    SurfaceId,
    /// Index of a [`cadre_geom::Curve3`] in [`crate::Model::curves`].
    CurveId,
    /// Index of a [`cadre_geom::Curve2`] (a pcurve) in [`crate::Model::pcurves`].
    PcurveId,
    /// Index of a [`crate::Vertex`].
    VertexId,
    /// Index of an [`crate::Edge`].
    EdgeId,
    /// Index of a [`crate::Face`].
    FaceId,
    /// Index of a [`crate::Shell`].
    ShellId,
    /// Index of a [`crate::Solid`].
    SolidId,
    /// Index of a [`crate::TriangleMesh`].
    MeshId,
    /// Index of a [`crate::Part`].
    PartId,
);
