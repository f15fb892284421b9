#!/usr/bin/env python3
"""Per-step amplification of an undamped spring mode under the two implicit steps
(docs/physics.md sections 5 and 11): the largest modulus of the eigenvalues of the map
(x, v) -> (x', v') at `omega dt`, unit mass and stiffness.

- backward Euler (the non-Brownian step; its damping, zero here, implicit): v' = v - dt k x,
  then x' = x + dt v' (sim/src/integrate/timestep.rs `damped_spring_limit`: determinant 1,
  trace 2 - (omega dt)^2).
- midpoint (the Brownian step, a spring whose stretch is advanced by the corrector's
  evaluation over the whole step, as the tangential contact spring is): the predictor's mean
  velocity W_p = v - dt/2 k x, the spring at x + dt W_p, W = v - dt/2 k (x + dt W_p),
  x' = x + dt W, v' = 2 W - v.

A modulus of 1 neither damps nor grows; below 1 the step damps the oscillation by itself,
above 1 it grows.

    python3 scripts/tangential_mode_amplification.py
"""
import cmath


def backward_euler(h):
    """The step's matrix for omega dt = h (k = m = 1)."""
    # v' = v - h x; x' = x + h v'
    return [[1.0 - h * h, h], [-h, 1.0]]


def midpoint_end_stretch(h):
    """The step's matrix for omega dt = h (k = m = 1), spring advanced over the whole step."""
    def step(x, v):
        w_p = v - 0.5 * h * x
        w = v - 0.5 * h * (x + h * w_p)
        return x + h * w, 2.0 * w - v
    (a, c), (b, d) = step(1.0, 0.0), step(0.0, 1.0)
    return [[a, b], [c, d]]


def spectral_radius(m):
    tr, det = m[0][0] + m[1][1], m[0][0] * m[1][1] - m[0][1] * m[1][0]
    root = cmath.sqrt(tr * tr - 4.0 * det)
    return max(abs((tr + root) / 2.0), abs((tr - root) / 2.0))


if __name__ == "__main__":
    print("omega dt | backward Euler | midpoint (spring over the whole step)")
    for h in [0.2, 0.4, 0.6, 0.8, 1.0, 1.2, 1.4, 1.5, 1.8, 2.0]:
        print(f"{h:8.1f} | {spectral_radius(backward_euler(h)):14.4f} | "
              f"{spectral_radius(midpoint_end_stretch(h)):.4f}")
