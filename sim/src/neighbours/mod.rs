//! Who interacts with whom: the cell list and the Verlet (neighbour) list built from it.

pub mod cell_list;
pub mod verlet_list;
