//! Surrogate models of local rheology (SPEC section 8). Filled in by issue 4.
