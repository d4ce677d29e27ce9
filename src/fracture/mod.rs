//! Fracture parameters and growth criteria (Guo & Nairn 2004; Guo & Nairn 001).
pub mod boundary3;
pub mod cohesive;
pub mod criteria;
pub mod front3;
pub mod growth;
pub mod growth3;
pub mod jintegral;
pub mod nodal;
pub mod release;
pub mod speed;
pub mod williams;
