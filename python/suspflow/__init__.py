"""suspflow from Python: scenes, simulations, surrogate models and the profile solver of the
Rust workspace, with NumPy and pandas in and out.

Units are the simulator's (docs/physics.md section 1): lengths in the radius ``a`` of the
small spheres, the fluid viscosity ``eta``, particle density ``rho`` and contact stiffness
``k_n`` set the others (all 1, 1 and 1e4 by default), so velocities are in ``a`` per unit
time, shear rates ``gdot`` in 1 / time, stresses ``sigma_xy`` and pressures ``P`` in
``eta`` / time, the drag density ``f_x`` in ``eta`` / (time a), and ``phi``, ``phi_loc``,
``J = eta gdot / P``, ``mu = |sigma_xy| / P``, ``Theta`` and ``Delta_v`` are dimensionless
(docs/physics.md sections 6 and 8 define the columns).

Functions: :func:`read_scene`, :func:`check`, :func:`simulate`, :func:`predict`,
:func:`generate`, :func:`green_kubo`, :func:`train`, :func:`validate`, :func:`cross_validate`,
:func:`flow_curves`,
:func:`read_dataset`, :func:`read_ensemble`, :func:`solve`. Every failure
raises a :class:`SuspflowError` with the crates' message (a bad scene names the field), of
the class of what failed: :class:`FileError` (a file missing, unreadable, locked or not
written), :class:`SceneError` (an invalid scene), :class:`ModelError` (a model that cannot
be loaded or does not fit the data), :class:`DataError` (a table with a missing column or a
cell that is not a number) or :class:`RunInterrupted` (a run stopped by a signal; Ctrl-C
raises KeyboardInterrupt). :mod:`suspflow.plain_models` uses the shipped models with plain
xgboost.
"""
from __future__ import annotations

import csv
import io
import json
import os
import pathlib
import sys
import warnings
from typing import Any, Callable, Dict, Mapping, Optional, Sequence, Union

import numpy as np
import pandas as pd

from . import _native
from ._native import (
    CODE_VERSION,
    DataError,
    FileError,
    ModelError,
    RunInterrupted,
    Scene,
    SceneError,
    SuspflowError,
)

__version__ = CODE_VERSION
"""The package's version and the commit it was built from (as ``suspflow --version``)."""

__all__ = [
    "CODE_VERSION",
    "DataError",
    "FileError",
    "ModelError",
    "RunInterrupted",
    "Scene",
    "SceneError",
    "SuspflowError",
    "check",
    "cross_validate",
    "flow_curves",
    "generate",
    "green_kubo",
    "predict",
    "read_dataset",
    "read_ensemble",
    "read_scene",
    "simulate",
    "solve",
    "train",
    "validate",
]

PathLike = Union[str, "os.PathLike[str]"]
SceneLike = Union[Scene, PathLike, Mapping[str, Any]]
TableLike = Union[pd.DataFrame, PathLike]


def read_scene(scene: SceneLike, strict: bool = False) -> Scene:
    """Reads and validates a scene: a TOML file (path), or a mapping with the scene file's
    keys (``{"name": ..., "box": {"l_x": 17.0, ...}, "particles": {"phi": 0.54}, "fluid":
    {"profile": "0.1*sin(2*pi*y/L)"}, ...}``; lengths in units of ``a``). ``strict`` refuses
    scenes that only warrant a warning (Stokes number >= 0.1). A :class:`Scene` is returned
    as it is."""
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, Mapping):
        field = _non_finite(scene)
        if field is not None:
            raise SuspflowError(
                f"scene field `{field[0]}`: {field[1]} is not a finite number "
                "(a scene holds no NaN or infinity)"
            )
        return Scene.from_json(json.dumps(scene), strict)
    return Scene.from_path(os.fspath(scene), strict)


def _non_finite(value: Any, path: str = "") -> Optional[tuple]:
    """The dotted path and value of the first NaN or infinity in a scene mapping, if any
    (JSON has neither, so the native reader would only say where in its text it stopped)."""
    if isinstance(value, float) and not np.isfinite(value):
        return path, value
    if isinstance(value, Mapping):
        items = ((f"{path}.{k}" if path else str(k), v) for k, v in value.items())
    elif isinstance(value, (list, tuple)):
        items = ((f"{path}[{k}]", v) for k, v in enumerate(value))
    else:
        return None
    for where, v in items:
        found = _non_finite(v, where)
        if found is not None:
            return found
    return None


def check(scene: SceneLike) -> Dict[str, Any]:
    """The derived quantities of a valid scene, as ``suspflow simulate --check`` prints them:
    ``n_particles``, ``species_counts``, ``phi`` (the packing's actual volume fraction),
    ``n_bins``, ``bin_width`` (a), ``box`` (a), ``memory_bytes``, ``gdot_max`` (1/time),
    ``rho``, ``stokes``, ``integrator``, ``dt`` (time) and ``dt_limit`` (what sets it), the
    critical steps ``contact_critical``, ``drag_critical``, ``lubrication_critical`` and the
    accuracy cap ``accuracy_limit`` (time), ``steps_per_strain``, ``max_strain``,
    ``snapshots`` and the validation ``warnings``."""
    return json.loads(read_scene(scene).check())


def _progress_line(report: Dict[str, Any]) -> None:
    """On a terminal, the run's status rewritten in place; elsewhere (a batch job's log,
    nohup, a notebook's captured output) a line every 10 % of a phase or 5 minutes, as the
    command writes them: phase, strain or snapshots, step, time spent and left."""
    if sys.stderr.isatty():
        sys.stderr.write(f"\r{report['status']:<100}")
    elif report["line"]:
        sys.stderr.write(report["line"] + "\n")
    else:
        return
    sys.stderr.flush()


def simulate(
    scene: SceneLike,
    out: PathLike,
    *,
    threads: int = 0,
    resume: bool = False,
    force: bool = False,
    snapshot: Optional[int] = None,
    snapshot_format: str = "xyz",
    progress: Union[bool, Callable[[Dict[str, Any]], None]] = True,
) -> Dict[str, Any]:
    """Runs a scene to its steady-state profile and writes the files of ``suspflow simulate``
    into the run folder ``out``: ``scene.toml``, ``profile.csv`` (one row per bin),
    ``stress.csv`` (the stress parts per bin), ``summary.json``, ``snapshot_sums.json`` and
    ``checkpoint.json`` (the state to continue from); with ``snapshot=N`` a particle frame every N samples to
    ``frames.xyz`` (``snapshot_format="xyz"``, extended XYZ) or ``frames.lammpstrj``
    (``"lammps"``, LAMMPS text dump), positions in a, velocities in a/time, spins in 1/time.

    ``threads``: 0 = all cores (a run is bit-identical to another with the same count).
    ``resume`` continues ``out/checkpoint.json``: an interrupted run, or a finished one whose
    scene now asks for more (``run.snapshots`` with ``run.blocks`` in proportion, or a larger
    ``run.max_strain``); an ``out`` holding an earlier run is refused unless ``resume`` or
    ``force`` (start over). The folder is locked while the run writes it. ``progress``: True writes a status line to
    standard error, False nothing, a callable receives a dict (``phase``, ``strain``,
    ``max_strain``, ``snapshots``, ``snapshots_target``, ``step``, ``status``: the status
    with the time spent and left, ``line``: the same when a log's line is due, else None)
    after every sample. The default writes ``status`` in place on a terminal and ``line``
    elsewhere.

    The run holds no GIL. Ctrl-C raises KeyboardInterrupt within 256 steps, after the state is
    saved in ``out/checkpoint.json`` (``resume=True`` continues it); so does an exception of
    the progress callable, which is re-raised. Returns the run summary (``summary.json``:
    ``n_particles``, ``dt``, ``steps``, ``strain_to_steady``, ``wall_s``, ...)."""
    scene = read_scene(scene)
    return _run_in_folder(
        out, resume, force, progress,
        ("profile.csv", "summary.json"),
        "the result of an earlier run; resume=True extends it to a longer scene",
        lambda out, callback: _native.simulate(
            scene, out, threads, not resume, snapshot, snapshot_format, callback
        ),
    )


def _run_in_folder(
    out: PathLike,
    resume: bool,
    force: bool,
    progress: Union[bool, Callable],
    results: tuple,
    what: str,
    run: Callable[[str, Optional[Callable]], str],
) -> Dict[str, Any]:
    """``run(out, callback)`` in the run folder ``out``, made (a file there is refused, and
    so is an earlier run's result, ``results`` whose first holds ``what``, or checkpoint
    unless ``resume`` continues it or ``force`` starts over), with the callback
    ``progress`` asks for (True: the status line); returns its JSON result parsed."""
    out = pathlib.Path(out)
    if out.exists() and not out.is_dir():
        raise FileError(f"{out} is a file; choose a directory for the run")
    if resume and force:
        raise SuspflowError("resume and force exclude each other")
    if not resume and not force:
        # The run folder's protocol (sim::RunFolder): a finished run has its results (and
        # keeps its final state for a longer run), an unfinished one only its checkpoint.
        finished = all((out / name).exists() for name in results)
        name, what = (
            (results[0], what)
            if finished
            else ("checkpoint.json", "the checkpoint of an unfinished run; resume=True continues it")
        )
        if (out / name).exists():
            raise FileError(
                f"{out / name} holds {what}; force=True starts over, or choose another out"
            )
    out.mkdir(parents=True, exist_ok=True)
    callback = _progress_line if progress is True else (progress or None)
    try:
        return json.loads(run(os.fspath(out), callback))
    finally:
        if progress is True and sys.stderr.isatty():
            sys.stderr.write("\n")


def green_kubo(
    scene: SceneLike,
    out: PathLike,
    *,
    warmup: float = 5.0,
    span: float = 100.0,
    every: int = 5,
    max_lag: float = 5.0,
    blocks: int = 10,
    threads: int = 0,
    resume: bool = False,
    force: bool = False,
    progress: Union[bool, Callable[[Dict[str, Any]], None]] = True,
) -> Dict[str, Any]:
    """The Green-Kubo Brownian viscosity of an unsheared Brownian scene (``fluid.kT > 0``,
    no flow; docs/physics.md section 11), as ``suspflow green-kubo``: runs it from its
    packing for ``warmup`` Brownian times ``tau_B``, samples the structural Brownian shear
    stress every ``every`` steps over ``span`` tau_B, and integrates its autocorrelation to
    the lag ``max_lag`` (tau_B), the error from ``blocks`` consecutive parts. Writes
    ``scene.toml``, ``green_kubo.csv`` (the correlation and its running integral),
    ``green_kubo.json`` and ``checkpoint.json`` into the run folder ``out``; ``resume``,
    ``force``, ``threads`` and ``progress`` as for :func:`simulate` (``resume`` also extends a
    finished run to a longer ``span``). Returns ``green_kubo.json``'s record:
    ``eta_brownian_over_eta`` (in units of the fluid viscosity, a part of ``eta_r``) and its
    standard error ``eta_brownian_over_eta_se``, the extrapolated value, ``tau_b``, ``phi_actual``
    and ``warnings``."""
    scene = read_scene(scene)
    return _run_in_folder(
        out, resume, force, progress,
        ("green_kubo.json", "green_kubo.csv"),
        "an earlier Green-Kubo result; resume=True extends it to a longer span",
        lambda out, callback: _native.green_kubo(
            scene, out, warmup, span, every, max_lag, blocks, threads, not resume, callback
        ),
    )


def generate(
    grid: PathLike,
    out: PathLike,
    *,
    shard: Optional[tuple] = None,
    jobs: int = 0,
    threads: int = 0,
    work: Optional[PathLike] = None,
    retry_failed: bool = False,
    force: bool = False,
    strict: bool = False,
    progress: Union[bool, Callable[[tuple], None]] = True,
) -> Dict[str, Any]:
    """Runs the scenes of a grid file (every replica as its own run), as ``suspflow
    generate``: each run in its folder under ``work`` (``<out>.work`` by default), ``jobs``
    at a time on ``threads`` threads each (0: one run per core, the cores shared), the
    longest first; finished runs are skipped and interrupted ones resume from their
    checkpoints, so calling it again continues. After every run it rewrites the dataset
    ``out`` (one row per bin per finished run, grid order), the run table
    ``<stem>.scenes.csv`` and, for a whole grid with replicas, the ensemble table
    ``<stem>.ensemble.csv``. ``shard=(i, n)`` runs part ``i`` of ``n`` disjoint parts of the
    runs (the parts write no ensemble table; ``suspflow merge`` joins them). Tables not
    written by this grid are replaced only with ``force``. ``progress``: True prints a line
    per run as it ends (to standard error), a callable gets ``(label, how, seconds)``.
    Returns ``{"done", "failed", "pending"}`` counts; raises :class:`SuspflowError` naming the
    failed runs (``retry_failed=True`` runs them again), KeyboardInterrupt on Ctrl-C."""
    if progress is True:
        progress = lambda end: print(  # noqa: E731
            f"{end[0]}: {end[1]} after {end[2]:.1f} s", file=sys.stderr, flush=True
        )
    done, failed, pending = _native.generate(
        os.fspath(grid),
        os.fspath(out),
        None if shard is None else (int(shard[0]), int(shard[1])),
        jobs,
        threads,
        None if work is None else os.fspath(work),
        retry_failed,
        force,
        strict,
        progress or None,
    )
    if pending:
        raise RunInterrupted(f"{pending} run(s) unfinished; call generate again to continue")
    if failed:
        reasons = "\n".join(f"  {label}: {reason}" for label, reason in failed)
        raise SuspflowError(
            f"{len(failed)} run(s) failed and are not in the dataset "
            f"(retry_failed=True runs them again):\n{reasons}"
        )
    return {"done": done, "failed": len(failed), "pending": pending}


def _table(data: TableLike) -> Union[bytes, str]:
    """A table for the Rust reader: a path as it is, a DataFrame as CSV bytes (shortest
    round-trip decimals, empty cells for NaN, as the datasets are written)."""
    if isinstance(data, pd.DataFrame):
        return data.to_csv(index=False).encode()
    return os.fspath(data)


def _model_path(model: PathLike, mapping: Optional[str]) -> tuple:
    """``(dir, mapping)`` of a model named ``DIR/<mapping>`` or given as ``DIR`` and ``mapping``."""
    path = pathlib.Path(model)
    if mapping is not None:
        return os.fspath(path), mapping
    name = path.name
    for suffix in (".meta.json", ".json"):
        if name.endswith(suffix):
            name = name[: -len(suffix)]
    return os.fspath(path.parent), name


def predict(
    model: PathLike, data: TableLike, mapping: Optional[str] = None, *, level: float = 0.9
) -> pd.DataFrame:
    """A trained mapping's predictions for every row of ``data`` (a DataFrame or a CSV path
    with the mapping's feature columns), as ``suspflow predict``: the model is
    ``DIR/<mapping>`` (e.g. ``models/dv``) or ``DIR`` with ``mapping``. Returns the input
    columns, one ``<output>_pred`` column per output (``phi_loc`` dimensionless, clipped into
    0 < phi_loc < 0.74; ``mu`` dimensionless, >= 0), the interval of each at ``level``
    (``<output>_lower``, ``<output>_upper``: the bounds between which the output of a row of a
    new flow lies with probability ``level``, calibrated on profile families the model did
    not see; absent, with a warning, for a model saved without intervals), ``in_domain``
    (whether the row lies in the model's training domain) and ``domain_distance`` (distance
    to the nearest training rows in units of the domain's threshold; <= 1 is near enough).
    ``attrs["clipped"]`` counts the clipped values, ``attrs["level"]`` is the intervals'
    level; warnings say how many rows lie outside the domain."""
    directory, name = _model_path(model, mapping)
    table = data if isinstance(data, pd.DataFrame) else read_dataset(data)
    p = _native.predict(directory, name, _table(data), level)
    result = table.copy()
    for output, values in zip(p.outputs, p.values):
        result[f"{output}_pred"] = np.asarray(values)
    if p.lower is None:
        warnings.warn(f"`{name}` was saved without intervals: predictions without error bars")
    else:
        for output, lower, upper in zip(p.outputs, p.lower, p.upper):
            result[f"{output}_lower"] = np.asarray(lower)
            result[f"{output}_upper"] = np.asarray(upper)
    result.attrs["level"] = p.level
    result["in_domain"] = np.asarray(p.in_domain, dtype=bool)
    result["domain_distance"] = np.asarray(p.domain_distance)
    result.attrs["clipped"] = p.clipped
    if p.clipped:
        warnings.warn(
            f"{p.clipped} predicted values of `{name}` left their physical range and were clipped"
        )
    outside = int((~result["in_domain"]).sum())
    if outside:
        warnings.warn(
            f"{outside} of {len(result)} rows lie outside the training domain of `{name}`: "
            "their predictions are extrapolations (in_domain = False)"
        )
    return result


def train(
    data: TableLike,
    out: PathLike,
    mappings: Optional[Sequence[str]] = None,
    *,
    tune: bool = True,
    params_from: Optional[PathLike] = None,
    bands: bool = True,
    force: bool = False,
    progress: Union[bool, Callable[[tuple], None]] = False,
) -> Dict[str, Any]:
    """Fits the surrogate mappings of docs/physics.md section 8 (``mu``, ``theta``, ``dv``,
    ``ext``; all four unless ``mappings`` names some) on ``data`` (the per-run table of
    :func:`generate` or its ensemble table, DataFrame or path) and saves them into the
    folder ``out``, as ``suspflow train``, the same files with the same numbers:
    ``<mapping>.json`` (XGBoost JSON), ``.meta.json``, ``.domain.json``, the intervals
    (``.intervals.json``, ``.quantiles_<output>.json``) and, when tuned, ``.tuning.json``.
    The hyper-parameters are chosen by cross-validation on ``data`` alone (``tune``, leaving
    one profile family out when there are at least three, else one simulation), taken from
    the models in ``params_from``, or XGBoost's defaults (``tune=False``). With ``bands``,
    when ``dv`` and ``theta`` are trained together, the bands of :func:`solve` are calibrated
    too (``bands.json``, every family's scenes solved with the models of its fold). Models
    already in ``out`` raise :class:`FileError` unless ``force``. ``progress``: True prints a
    line per step to standard error, a callable gets ``(step, name)`` (``("tuned", mapping)``,
    ``("intervals", mapping)``, ``("trained", mapping)``, ``("bands", family)``). The work
    holds no GIL; Ctrl-C (or an exception of ``progress``) stops it before the next mapping
    or the bands, the models saved until then kept, and is raised.

    Returns what the command prints: ``mappings``, per mapping its ``rows`` and
    ``skipped_rows``, ``params``, ``tuning`` (settings, folds, ``left_out``, the ``chosen``
    and ``defaults`` scores: relative L2 error per output, a fraction; None untuned),
    ``training_error`` (per output, a fraction), ``intervals`` (``level``, ``folds``,
    ``held_out``, ``fold_coverage``, ``fold_mean_width`` in output units; None with the
    reason in ``without_intervals``) and ``fit_seconds``; ``bands`` (``status``:
    ``calibrated`` with ``folds`` and per closure the held-out bins' ``fold_coverage`` of u,
    phi_loc and mu, ``skipped``, ``not_trained`` or ``too_few_families``); ``seconds``. What
    the command warns of is a warning here."""
    if progress is True:
        progress = lambda step: print(  # noqa: E731
            f"train: {step[1]}: {step[0]}", file=sys.stderr, flush=True
        )
    result = json.loads(
        _native.train(
            _table(data),
            os.fspath(out),
            list(mappings or []),
            tune,
            None if params_from is None else os.fspath(params_from),
            bands,
            force,
            progress or None,
        )
    )
    for m in result["mappings"]:
        if m["skipped_rows"]:
            warnings.warn(
                f"{m['mapping']}: {m['skipped_rows']} rows skipped: an empty cell in one of "
                f"{', '.join(m['features'] + m['outputs'])}"
            )
        if m["tuning"] and m["tuning"]["backbone_excluded"]:
            warnings.warn(
                f"{m['mapping']}: settings with the physics backbone left out of the search: "
                f"{m['tuning']['backbone_excluded']}"
            )
        if m["without_intervals"]:
            warnings.warn(f"{m['mapping']}: saved without intervals: {m['without_intervals']}")
    b = result["bands"]
    if b["status"] == "not_trained" and b["kept"]:
        warnings.warn(
            f"{b['kept']} was left as it was: the bands of solve are calibrated when dv and "
            "theta are trained together"
        )
    elif b["status"] == "too_few_families":
        warnings.warn(
            f"no bands for solve: they are calibrated leaving one profile family out, and "
            f"{b['mapping']}'s folds left out {b['held_out']}"
        )
    return result


def validate(
    models: PathLike,
    data: TableLike,
    mappings: Optional[Sequence[str]] = None,
    *,
    level: float = 0.9,
) -> pd.DataFrame:
    """The trained mappings (all of ``mu``, ``theta``, ``dv``, ``ext`` in ``models`` unless
    ``mappings`` names some) on a validation table (per-run or ensemble table, DataFrame or
    path): one row per mapping, output and profile (the ``profile`` column, then all
    profiles together and the rows inside and outside the training domain) with ``rel_l2``,
    the relative L2 error of eq 6.6 on outputs min-max scaled with the training ranges (a
    fraction, not a percent), ``beyond_noise`` (its part beyond the targets' own noise,
    ``sqrt(max(0, rel_l2^2 - noise^2))``; NaN without standard errors), ``coverage`` (the
    fraction of the rows inside their interval at ``level``) and ``interval_width`` (the
    intervals' mean width, output units): the records of ``suspflow validate --json``."""
    records = _native.validate(os.fspath(models), _table(data), list(mappings or []), level)
    columns = [
        "mapping", "output", "profile", "rel_l2", "beyond_noise", "coverage", "interval_width"
    ]
    frame = pd.DataFrame(records, columns=columns)
    for c in columns[4:]:
        frame[c] = frame[c].astype(float)
    return frame


def cross_validate(
    data: TableLike,
    models: PathLike = "models",
    mappings: Optional[Sequence[str]] = None,
    *,
    learning_curve: Sequence[int] = (),
    draws: int = 3,
    seed: int = 1,
    level: float = 0.9,
) -> Dict[str, Any]:
    """Leave-one-family-out cross-validation, as ``suspflow cross-validate`` (the mappings
    named, all four by default): a profile family is every row of one forcing (the
    ``profile`` column, at least two families). Each fold fits, on the other families'
    rows, XGBoost alone, the physics backbone alone and backbone + XGBoost, the trees with
    the hyper-parameters of the models in ``models`` (train first), and measures the
    relative L2 error of eq 6.6 (a fraction) on the held-out rows, all of them and those
    inside and outside the fold's training domain. ``learning_curve`` (numbers of training
    families, each with ``draws`` draws seeded by ``seed``) adds the error against the
    number of families; the intervals' coverage at ``level`` is measured on the same folds.
    Returns the record the command writes to ``cv.json``: ``mappings`` (per mapping its
    ``folds`` and ``summary``), ``learning_curves``, ``intervals``, ``families`` and the
    data's ``fnv1a_64``."""
    record = _native.cross_validate(
        os.fspath(models),
        _table(data),
        list(mappings or []),
        list(learning_curve),
        draws,
        seed,
        level,
    )
    return json.loads(record)


def flow_curves(
    grid: PathLike,
    runs: Union[PathLike, Sequence[PathLike]],
    green_kubo: Sequence[PathLike] = (),
    table: Optional[PathLike] = None,
) -> tuple:
    """The flow curves of a grid of homogeneous-shear scenes (docs/physics.md section 10)
    that ``suspflow generate`` ran into the work folder ``runs`` (or a list of them, one per
    ``--shard`` of the grid), as ``suspflow
    flow-curves``, with the Green-Kubo runs in the folders ``green_kubo`` (replicas of the
    grid's volume fractions). With ``table``, a ``flow_curves.csv`` written earlier for the
    grid, the runs (part of the grid run again, after a change of the code, say) replace its
    lines of the same scenes, each line keeping its run's ``code_version``, as
    ``flow-curves --table``; with ``table`` and no runs (``runs=[]``) the table alone gives
    the curves. Returns ``(table, fits)``: ``table`` holds the rows of
    ``flow_curves.csv``, one per finished run (box totals ``sigma_xy``, ``P`` in ``eta`` /
    time; ``eta_r``, ``mu``, ``J`` and the parts of ``eta_r``, dimensionless, each with its
    standard error ``_se``); ``fits`` one row per state (``mu_p``, ``peclet``, ``alpha``,
    ``rho``, ``dt_factor``: the multiple of the automatic time step, ``dt``: the fixed step
    where the scene sets one, else NaN) and stress ``convention`` of the jamming law
    ``eta_r = (1 - phi/phi_J)^-lambda``: ``phi_J``, ``phi_J_se``, ``lambda``, ``lambda_se``
    (NaN with the reason in ``error`` where the points cannot be fitted). Runs not finished
    are named in a warning."""
    folders = [runs] if isinstance(runs, (str, os.PathLike)) else list(runs)
    text, fits, missing = _native.flow_curves(
        os.fspath(grid),
        [os.fspath(r) for r in folders],
        [os.fspath(g) for g in green_kubo],
        None if table is None else os.fspath(table),
    )
    if missing:
        where = runs if table is None else f"{runs} or {table}"
        warnings.warn(f"{len(missing)} runs not finished in {where}: {', '.join(missing)}")
    rows = [
        (mu_p, peclet, alpha, rho, dt_factor, np.nan if dt is None else dt, convention,
         *(values or [np.nan] * 4), error)
        for mu_p, peclet, alpha, rho, dt_factor, dt, convention, values, error in fits
    ]
    columns = [
        "mu_p", "peclet", "alpha", "rho", "dt_factor", "dt", "convention",
        "phi_J", "phi_J_se", "lambda", "lambda_se", "error",
    ]
    return _exact_table(text), pd.DataFrame(rows, columns=columns)


def _exact_table(text: str) -> pd.DataFrame:
    """A CSV text as a DataFrame with every number exactly the decimal written (Python's
    float), empty cells NaN, other columns as strings."""
    lines = list(csv.reader(io.StringIO(text)))
    columns = {}
    for j, name in enumerate(lines[0]):
        cells = [r[j] for r in lines[1:]]
        try:
            columns[name] = [np.nan if c == "" else float(c) for c in cells]
        except ValueError:
            columns[name] = cells
    return pd.DataFrame(columns)


def read_dataset(path: PathLike) -> pd.DataFrame:
    """A dataset (one row per bin per run) or an ensemble table (one row per bin per scene,
    averaged over replicas) as the commands read it: columns whose every cell is a number as
    floats (an empty cell, an undefined value, as NaN), ``seed`` and ``replicas`` as integers,
    the others as strings.
    ``attrs["kind"]`` is ``"runs"``, ``"ensemble"`` (None for a table without scene ids) and
    ``attrs["description"]`` says how many scenes, runs or replicas it holds."""
    columns, kind = _native.read_dataset(os.fspath(path))
    def column(values):
        if values and isinstance(values[0], int):
            return np.asarray(values, dtype=np.int64)
        if values and isinstance(values[0], float):
            return np.asarray(values, dtype=float)
        return pd.Series(values, dtype=object)

    frame = pd.DataFrame({name: column(values) for name, values in columns})
    frame.attrs["kind"], frame.attrs["description"] = kind if kind else (None, None)
    return frame


def read_ensemble(path: PathLike) -> pd.DataFrame:
    """An ensemble table (``<stem>.ensemble.csv`` of ``generate`` or ``merge``: per scene and
    bin each observable's mean over the replicas, its standard error ``<column>_se`` and
    the replica count) as a DataFrame, like :func:`read_dataset`; other tables are refused."""
    frame = read_dataset(path)
    if frame.attrs["kind"] != "ensemble":
        raise DataError(
            f"{path} is not an ensemble table (it has no `replicas` and `se_from` columns)"
        )
    return frame


def solve(
    scene: SceneLike,
    models: PathLike = "models",
    closure: str = "learned",
    *,
    train: Optional[PathLike] = None,
    p_start: float = 0.1,
    level: float = 0.9,
) -> pd.DataFrame:
    """The steady profile of a scene from its forcing alone (``suspflow solve``): bin
    velocities ``u`` (a/time) and one pressure ``P`` (eta/time) that balance the face stress
    ``-sign(gdot) mu P`` against the drag density ``6 pi eta <a>/<V_p> phi_loc (u_inf - u)``
    (``u_inf`` averaged over each bin) with ``mean(phi_loc) = phi`` (docs/physics.md section
    8), closed by ``closure``:
    ``"learned"`` (the ``dv`` model in ``models``), ``"local"`` (the local rheology fitted
    on ``train``, by default the ``dv`` model's training data), ``"nonlocal"`` (the
    ``theta`` model with the Theta balance fitted on the same data) or ``"extremum"`` (the
    ``ext`` model, whose input ``d_ext`` is each bin's distance to the nearest velocity
    extremum of the solved profile). Newton iterations start from ``p_start`` (eta/time),
    continued from the local law where they stall. Returns one row per bin with the columns
    of ``suspflow solve``'s profile.csv (``scene_id``, ``profile``, ``L_y``, ``phi``, ``y``,
    ``u_inf``, ``u``, ``gdot``, ``sigma_xy``, ``P``, ``phi_loc``, ``J``, ``mu``, ``Theta``
    (NaN unless nonlocal), ``Delta_v``, ``f_x``, ``d_ext``, the bands at ``level``
    ``u_lower``, ``u_upper``, ``phi_loc_lower``, ``phi_loc_upper``, ``mu_lower``,
    ``mu_upper`` (where the simulated profile lies with probability ``level`` bin by bin,
    calibrated on families the models did not see; absent, with a warning, when the models
    have no ``bands.json``), ``in_domain``, ``domain_distance``); ``attrs`` holds
    ``iterations``, ``continued``, ``residual`` (largest balance residual in units of the
    forcing's drag density), ``pressure`` and ``bands`` (level, margins, relative widths and
    held-out coverage, as summary.json's, or None)."""
    scene = read_scene(scene)
    s = _native.solve(
        scene,
        os.fspath(models),
        closure,
        None if train is None else os.fspath(train),
        p_start,
        level,
    )
    if s.bands_missing is not None:
        warnings.warn(f"the profile has no bands: {s.bands_missing}")
    file = json.loads(scene.to_json())
    n = len(s.columns[0][1])
    frame = pd.DataFrame({"scene_id": [file["name"]] * n, "profile": [file["fluid"]["profile"]] * n})
    for name, values in s.columns:
        frame[name] = np.asarray(values)
    frame["in_domain"] = np.asarray(s.in_domain)
    frame["domain_distance"] = np.asarray(s.domain_distance)
    frame.attrs.update(
        iterations=s.iterations,
        continued=s.continued,
        residual=s.residual,
        pressure=s.pressure,
        bands=None if s.bands is None else json.loads(s.bands),
    )
    return frame
