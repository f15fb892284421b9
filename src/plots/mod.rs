//! SVG figures: profiles along y (`profile_panels`), log-log error curves (`loglog`), the
//! stability map (`stability_map`) and scatter plots of dataset rows (`scatter_panels`).

pub mod loglog;
pub mod profile_panels;
pub mod scatter_panels;
pub mod stability_map;
