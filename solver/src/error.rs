//! The crate's single error type.

/// Why a Newton solve stopped before its residual reached the tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stall {
    /// The iteration limit (the number held) was reached.
    IterationLimit(usize),
    /// The Jacobian has no inverse: the closure does not change with the local state.
    SingularJacobian,
    /// The last fresh Jacobians (the number held) did not halve the residual: the iterate
    /// sits on a kink of the trees that Newton's method does not leave.
    NoProgress(usize),
}

/// Why Newton's method can stall on a learned closure, for the messages of [`Stall`].
fn trees_are_piecewise_constant() -> String {
    format!(
        "a closure of boosted trees is piecewise constant, smoothed only over +-{:.0} % in J \
         and Delta_v, Theta or d_ext",
        100.0 * crate::smoothing::SMOOTHING
    )
}

impl std::fmt::Display for Stall {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Stall::IterationLimit(limit) => write!(
                f,
                "{limit} iterations were not enough ({})",
                trees_are_piecewise_constant()
            ),
            Stall::SingularJacobian => write!(
                f,
                "the Jacobian is singular: the closure does not change with the local state \
                 here, as trees do beyond their training range"
            ),
            Stall::NoProgress(window) => write!(
                f,
                "{window} Newton iterations in a row did not halve the residual ({})",
                trees_are_piecewise_constant()
            ),
        }
    }
}

/// Everything that can go wrong in this crate, with enough context to act on the message.
#[derive(Debug, thiserror::Error)]
pub enum SolverError {
    /// The solve stopped before its residual reached the tolerance.
    #[error(
        "the profile solve did not converge: {stall}; largest scaled residual {residual:.3e} \
         after {iterations} Newton iterations (tolerance {tolerance:.0e})"
    )]
    NotConverged {
        stall: Stall,
        iterations: usize,
        residual: f64,
        tolerance: f64,
    },

    /// Every attempt of the solve stalled: Newton's method from the local law's solution,
    /// the continuation from the law (at weight `reached` of the closure), and Newton's
    /// method from `u = u_inf` (`direct`).
    #[error(
        "the continuation from the local law stalled at weight {reached:.3} of the closure \
         (steps down to 1/64; largest scaled residual {residual:.3e}), and from u = u_inf {direct}"
    )]
    ContinuationStalled {
        direct: Box<SolverError>,
        reached: f64,
        residual: f64,
    },

    /// A problem, scene or closure the solver cannot take.
    #[error("invalid argument: {0}")]
    InvalidArgument(String),

    /// A solution's files could not be written or read.
    #[error("{path}: {message}")]
    File { path: String, message: String },

    /// A file that holds a user's work would be replaced, and replacing was not asked for.
    #[error("{} already exists ({what})", path.display())]
    WouldReplace {
        path: std::path::PathBuf,
        what: String,
    },

    /// A job stopped at its interrupt, with the models of the mappings `saved` written.
    #[error(
        "interrupted before every mapping was trained (models saved: {})",
        if saved.is_empty() { "none".to_owned() } else { saved.join(", ") }
    )]
    Interrupted { saved: Vec<String> },

    /// A step of a longer job failed: `doing` says which (e.g. "saving the dv model"), the
    /// error's source why.
    #[error("{doing}")]
    During {
        doing: String,
        source: Box<SolverError>,
    },

    /// A closure or a dataset failed in the surrogate crate.
    #[error(transparent)]
    Surrogate(#[from] surrogate::SurrogateError),
}

impl SolverError {
    /// This error as the failure of the step `doing`.
    pub fn during<E: Into<Self>>(doing: impl Into<String>) -> impl FnOnce(E) -> Self {
        let doing = doing.into();
        move |e| SolverError::During {
            doing,
            source: Box::new(e.into()),
        }
    }
}

/// Result type of this crate.
pub type Result<T> = std::result::Result<T, SolverError>;
