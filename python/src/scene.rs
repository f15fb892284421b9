//! `Scene`: a validated scene (sim::Scene) read from a TOML file or from the JSON text of a
//! mapping with the same keys, and its derived quantities (`suspflow simulate --check`).
use crate::error::Error;
use pyo3::prelude::*;
use sim::input::memory_estimate;
use sim::{SceneFile, SimError};
use std::path::PathBuf;

/// A validated scene.
#[pyclass(module = "suspflow._native", frozen)]
pub struct Scene {
    pub inner: sim::Scene,
}

#[pymethods]
impl Scene {
    /// Reads and validates a scene file (TOML); `strict` refuses scenes that only warrant a
    /// warning (Stokes number >= 0.1).
    #[staticmethod]
    #[pyo3(signature = (path, strict = false))]
    fn from_path(path: PathBuf, strict: bool) -> Result<Self, Error> {
        Ok(Scene {
            inner: sim::Scene::from_path(&path, strict)?,
        })
    }

    /// Validates a scene given as the JSON text of a mapping with the scene file's keys.
    #[staticmethod]
    #[pyo3(signature = (text, strict = false))]
    fn from_json(text: &str, strict: bool) -> Result<Self, Error> {
        let file: SceneFile = serde_json::from_str(text).map_err(|e| SimError::SceneFile {
            path: "<mapping>".into(),
            message: e.to_string(),
        })?;
        Ok(Scene {
            inner: sim::Scene::from_file(file, strict)?,
        })
    }

    /// The scene with every default filled in, as JSON text.
    fn to_json(&self) -> String {
        serde_json::to_string(&self.inner.file).expect("a scene file serialises")
    }

    /// The scene's name.
    #[getter]
    fn name(&self) -> &str {
        &self.inner.file.name
    }

    /// Warnings of the validation (e.g. a Stokes number near the inertia-free limit).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }

    /// Derived quantities as JSON text: particle counts, bins, memory estimate, Stokes
    /// number, time step and what limits it, steps per unit strain (`suspflow simulate
    /// --check`).
    fn check(&self) -> String {
        let s = &self.inner;
        let t = s.timestep;
        let r = &s.file.run;
        serde_json::json!({
            "name": s.file.name,
            "n_particles": s.n_particles(),
            "species_counts": s.counts,
            "phi": s.phi_actual,
            "n_bins": s.n_bins,
            "bin_width": r.bin_width,
            "box": s.box_len,
            "memory_bytes": s.memory_bytes,
            "memory": memory_estimate::describe(s.memory_bytes),
            "gdot_max": s.gdot_max(),
            "rho": s.rho,
            "stokes": s.stokes,
            "integrator": t.integrator.to_string(),
            "dt": t.dt,
            "dt_limit": t.limit.to_string(),
            "contact_critical": t.contact_critical,
            "drag_critical": t.drag_critical,
            "lubrication_critical": t.lubrication_critical,
            "accuracy_limit": t.accuracy_limit,
            "steps_per_strain": s.steps_per_strain(),
            "max_strain": r.max_strain,
            "snapshots": r.snapshots,
            "warnings": s.warnings,
        })
        .to_string()
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene(name={:?}, n_particles={}, n_bins={})",
            self.inner.file.name,
            self.inner.n_particles(),
            self.inner.n_bins
        )
    }
}
