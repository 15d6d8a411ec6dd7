//! The solver-neutral cone program assembled from the model (kept apart from solving).

pub mod cone_program;
