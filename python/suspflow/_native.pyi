"""Typed stubs of the native module `suspflow._native` (the Rust bindings under python/src).
Use the wrappers in `suspflow` (DataFrames in and out); units are stated there."""
from typing import Callable, Dict, List, Optional, Sequence, Tuple, Union

CODE_VERSION: str
"""The code version stamped into every result file (`code_version` column)."""

class SuspflowError(Exception):
    """An error of the simulator, the surrogate models or the profile solver."""

class FileError(SuspflowError):
    """A file missing, unreadable, locked by another run, or not written."""

class SceneError(SuspflowError):
    """An invalid scene."""

class ModelError(SuspflowError):
    """A model that cannot be loaded or does not fit the data."""

class DataError(SuspflowError):
    """A table with a missing column or a cell that is not a number or not physical."""

class RunInterrupted(SuspflowError):
    """A run stopped by a signal (its checkpoint holds its state)."""

class Scene:
    """A validated scene (lengths in units of the small-sphere radius a)."""

    @staticmethod
    def from_path(path: str, strict: bool = False) -> "Scene": ...
    @staticmethod
    def from_json(text: str, strict: bool = False) -> "Scene": ...
    def to_json(self) -> str:
        """The scene file with every default filled in, as JSON text."""
    def check(self) -> str:
        """Derived quantities (`suspflow simulate --check`) as JSON text."""
    @property
    def name(self) -> str: ...
    @property
    def warnings(self) -> List[str]: ...

class Predictions:
    outputs: List[str]
    values: List[List[float]]
    in_domain: List[bool]
    in_range: List[bool]
    domain_distance: List[float]
    clipped: int
    level: float
    lower: Optional[List[List[float]]]
    upper: Optional[List[List[float]]]

class Solution:
    columns: List[Tuple[str, List[float]]]
    in_domain: List[bool]
    domain_distance: List[float]
    iterations: int
    continued: bool
    residual: float
    pressure: float
    bands: Optional[str]
    bands_missing: Optional[str]

Table = Union[bytes, str]
"""A CSV path, or the bytes of a CSV text."""

def simulate(
    scene: Scene,
    out: str,
    threads: int = 0,
    fresh: bool = True,
    snapshot: Optional[int] = None,
    snapshot_format: str = "xyz",
    progress: Optional[Callable[[Dict[str, object]], None]] = None,
) -> str:
    """Runs `scene` into the run folder `out` (continuing its checkpoint unless `fresh`); returns summary.json's text."""

def generate(
    grid: str,
    out: str,
    shard: Optional[Tuple[int, int]] = None,
    jobs: int = 0,
    threads: int = 0,
    work: Optional[str] = None,
    retry_failed: bool = False,
    force: bool = False,
    strict: bool = False,
    progress: Optional[Callable[[Tuple[str, str, float]], None]] = None,
) -> Tuple[int, List[Tuple[str, str]], int]:
    """Runs a grid (or a shard of it) and writes its tables; returns (done, failed, pending)."""

def green_kubo(
    scene: Scene,
    out: str,
    warmup: float = 5.0,
    span: float = 100.0,
    every: int = 5,
    max_lag: float = 5.0,
    blocks: int = 10,
    threads: int = 0,
    fresh: bool = True,
    progress: Optional[Callable[[Dict[str, object]], None]] = None,
) -> str:
    """Runs the Green-Kubo run of `scene` into `out` (continuing its checkpoint unless `fresh`); returns green_kubo.json's text."""

def predict(dir: str, mapping: str, table: Table, level: float = 0.9) -> Predictions: ...
def validate(
    dir: str, table: Table, mappings: Sequence[str] = ..., level: float = 0.9
) -> List[
    Tuple[str, str, str, float, Optional[float], Optional[float], Optional[float]]
]: ...
def cross_validate(
    dir: str,
    table: Table,
    mappings: Sequence[str] = ...,
    learning_curve: Sequence[int] = ...,
    draws: int = 3,
    seed: int = 1,
    level: float = 0.9,
) -> str:
    """The leave-one-family-out study of `table`; returns cv.json's record as JSON text."""

def train(
    table: Table,
    out: str,
    mappings: Sequence[str] = ...,
    tune: bool = True,
    params_from: Optional[str] = None,
    bands: bool = True,
    force: bool = False,
    progress: Optional[Callable[[Tuple[str, str]], None]] = None,
) -> str:
    """Trains the mappings of `table` into `out` as `suspflow train`; returns the result as JSON text."""

def flow_curves(
    grid: str, runs: Sequence[str], green_kubo: Sequence[str] = ..., table: Optional[str] = None
) -> Tuple[
    str,
    List[
        Tuple[
            float, float, Optional[float], float, float, Optional[float], str,
            Optional[Tuple[float, float, float, float]], Optional[str],
        ]
    ],
    List[str],
]:
    """flow_curves.csv's text, the jamming-law fits per state and convention, the runs not finished."""

def read_dataset(
    path: str,
) -> Tuple[List[Tuple[str, Union[List[float], List[str]]]], Optional[Tuple[str, str]]]: ...
def solve(
    scene: Scene,
    models: str,
    closure: str = "learned",
    train: Optional[str] = None,
    p_start: float = 0.1,
    level: float = 0.9,
) -> Solution: ...
