//! Who interacts with whom: the cell lists (one, or one per size class of a mixture) and
//! the Verlet (neighbour) list built from them.

pub mod cell_list;
pub mod size_classes;
pub mod verlet_list;
