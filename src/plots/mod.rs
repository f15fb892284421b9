//! SVG figures: profiles along y (`profile_panels`), log-log error curves (`loglog`) and the
//! stability map (`stability_map`).

pub mod loglog;
pub mod profile_panels;
pub mod stability_map;
