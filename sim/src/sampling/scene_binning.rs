//! The constants that turn a scene's snapshot sums into observables: its bins along y, their
//! volume and face area, the fluid viscosity, the mean radius, the streaming velocity at the
//! bin centres and the Lees-Edwards image velocity (docs/physics.md sections 6 and 10).
use crate::input::scene::Scene;
use crate::sampling::bin_averages::BinningContext;
use crate::sampling::binning::Bins;

impl BinningContext {
    /// The binning of `scene`: bins of width `run.bin_width` (units a), bin volume
    /// `L_x w L_z`, face area `L_x L_z`, `u_inf` at the bin centres, image velocity
    /// `gdot L_y` of a sheared box (0 otherwise).
    pub fn for_scene(scene: &Scene) -> Self {
        let [l_x, _, l_z] = scene.box_len;
        let w = scene.file.run.bin_width;
        let bins = Bins::new(w, scene.n_bins);
        Self {
            bins,
            bin_volume: l_x * w * l_z,
            face_area: l_x * l_z,
            eta: scene.file.fluid.eta,
            a_mean: scene.mean_radius(),
            u_inf: (0..scene.n_bins)
                .map(|k| scene.profile.u(bins.centre(k)))
                .collect(),
            conventions: scene.file.observables,
            image_velocity: scene
                .shear_rate()
                .map_or(0.0, |gdot| gdot * scene.box_len[1]),
        }
    }
}
