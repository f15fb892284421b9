//! SVG figures: profiles along y (`profile_panels`), log-log error curves (`loglog`), the
//! stability map (`stability_map`), measured points beside model curves (`data_and_laws`)
//! on a shared frame (`chart_frame`), scatter plots of dataset rows (`scatter_panels`), and
//! `validate`'s simulated and predicted profiles (`validation_figures`).
//! Every axis label states its unit (`axis_label`); every figure's numbers are written
//! beside it as CSV (`figure_data`).

pub mod axis_label;
pub mod chart_frame;
pub mod data_and_laws;
pub mod figure_data;
pub mod flow_curves;
pub mod loglog;
pub mod profile_panels;
pub mod scatter_panels;
pub mod stability_map;
pub mod validation_figures;
