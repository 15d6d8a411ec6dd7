//! The immutable contact model built from a scene: materials, patches, influence coefficients
//! (patch compliance, as a dense matrix or an FFT operator), friction laws, the equilibrium
//! map, and the closed forms the model is checked against.

pub mod circulant_inverse;
pub mod closed_form;
pub mod compliance_operator;
pub mod contact_pair;
pub mod elastic_layer;
pub mod equilibrium;
pub mod finger_mount;
pub mod friction;
pub mod grasp_model;
pub(crate) mod grid_coarsening;
pub(crate) mod grid_fft;
pub mod influence;
pub mod influence_at_depth;
pub mod layer_green_function;
pub mod layer_kernels;
pub mod material;
pub mod model_builder;
pub mod patch;
pub mod patch_compliance;
pub mod quadrature;
pub mod shared_spring;
pub mod spring_loads;
pub mod surface_gap;
pub mod viscoelasticity;
pub mod viscous_contact;
