//! Crack-face contact at nodes with two velocity fields (Nairn 2003 §2.2, eqs. 8–19).
//! (Being built: the crack issue.)

use crate::simulation::Simulation;

impl Simulation {
    /// Contact on momenta extrapolated from the particles (Tasks 2 and 6c).
    pub(crate) fn apply_contact_to_momenta(&mut self) {}

    /// Contact on the momenta of Task 4, with the total forces back-computed.
    pub(crate) fn apply_contact_to_updated_momenta(&mut self) {}
}
