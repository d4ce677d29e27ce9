//! Explicit cracks (Nairn 2003 §2): massless crack particles joined into polylines,
//! the line-crossing test that assigns each particle–node pair its velocity field,
//! and the crack surfaces.

pub mod geometry;

use crate::dim::Vector;
use serde::{Deserialize, Serialize};

/// How the two faces of a crack interact where they touch (Nairn 2003 §2.2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum ContactLaw {
    /// Faces never interact (they may interpenetrate).
    None,
    /// Stick: both fields take the centre-of-mass momentum (eq. 13).
    Stick,
    /// Frictional sliding with coefficient μ (eqs. 14–19); μ = 0 is frictionless.
    Friction(f64),
}

/// One crack: its crack particles in order along the polyline, and its contact law.
#[derive(Clone, Debug, PartialEq)]
pub struct Crack {
    pub points: Vec<Vector>,
    pub contact: ContactLaw,
    /// Relative nodal volume below which the faces are separated (eq. 10).
    pub v_sep: f64,
    /// Relative nodal volume above which the faces are in contact.
    pub v_contact: f64,
}

use crate::check::CheckError;
use crate::simulation::Simulation;

impl Simulation {
    /// Task 1 with cracks: ν(p,i) for every pair by the line-crossing algorithm.
    pub(crate) fn assign_velocity_fields(&mut self) -> Result<(), CheckError> {
        Ok(())
    }

    /// Task 7: move the crack particles in the centre-of-mass velocity of the nodes (eq. 32).
    pub(crate) fn task7_move_cracks(&mut self) {}
}
