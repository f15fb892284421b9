//! The simulator's error type.
use thiserror::Error;

/// Every failure the simulator reports: bad input names the field, runtime failures name the step and particle.
#[derive(Debug, Error)]
pub enum SimError {
    /// A scene field has an invalid value.
    #[error("scene field `{field}`: {message}")]
    Field { field: String, message: String },
    /// A Green-Kubo integral asked of a series too short for its lag and blocks.
    #[error("Green-Kubo integral: {0}")]
    GreenKubo(String),

    #[error("benchmark: {0}")]
    Benchmark(String),
    /// The flow profile expression does not parse, is not finite, or is not periodic.
    #[error("flow profile `{expr}`: {message}")]
    Profile { expr: String, message: String },
    /// The initial configuration could not be built.
    #[error("initial packing: {0}")]
    Packing(String),
    /// The scene file could not be read or parsed.
    #[error("scene file {path}: {message}")]
    SceneFile { path: String, message: String },
    /// The integration became unstable.
    #[error("blow-up at step {step} (t = {time:.4}), particle {particle}: {what}. Likely cause: {cause}")]
    BlowUp {
        step: u64,
        time: f64,
        particle: usize,
        what: String,
        cause: String,
    },
    /// The run finished, but its momentum balance says its dynamics were wrong.
    #[error("momentum residual {residual:.3} of the drag scale, above the {limit} that correct runs stay below: the dynamics are wrong, most likely a time step ({dt:.3e}, set by {dt_limit}) beyond its stability limit; lower run.dt_factor, run.dt_safety or run.dt")]
    MomentumImbalance {
        residual: f64,
        limit: f64,
        dt: f64,
        dt_limit: String,
    },
    /// The run did not reach a steady state within its strain budget.
    #[error("no steady state within the budget of strain {budget}: {detail}")]
    NotSteady { budget: f64, detail: String },
    /// A checkpoint could not be written.
    #[error("checkpoint {path}: {message}")]
    Checkpoint { path: String, message: String },
    /// An existing checkpoint cannot be resumed: unreadable, damaged, or of another scene.
    /// (The command says how to go on: remove it, or start over.)
    #[error("checkpoint {path}: {message}")]
    CheckpointUnusable { path: String, message: String },
    /// Another process holds the lock of an output.
    #[error("{what} is in use by another {holder} (process {owner}, lock {lock}); wait for it to finish, or stop it (its work is kept) and run again")]
    Locked {
        what: String,
        holder: String,
        owner: String,
        lock: String,
    },
    /// Writing results failed.
    #[error("writing {path}: {message}")]
    Output { path: String, message: String },
    /// A dataset table could not be read or combined.
    #[error(transparent)]
    Table(#[from] schema::SchemaError),
    /// A grid file is invalid or expands to an invalid scene.
    #[error("grid {0}")]
    Grid(String),
    /// The run was interrupted (Ctrl-C, SIGTERM); the last checkpoint holds its state.
    #[error("interrupted at step {step}; the checkpoint holds its state")]
    Interrupted { step: u64 },
    /// The run was interrupted during the initial packing, before any state worth saving:
    /// the packing is drawn again from the scene's seed.
    #[error("interrupted during the initial packing; nothing to save (the packing is drawn again from the scene's seed)")]
    InterruptedPacking,
}

impl SimError {
    /// Shorthand for a field error.
    pub fn field(field: &str, message: impl Into<String>) -> Self {
        SimError::Field {
            field: field.to_string(),
            message: message.into(),
        }
    }
}
