"""
Wrist force/torque sensor: strain gauges on four spokes, V = H F (7.10), F = H^S V (7.11).

Book §7.6, fig. 7.25 (seed catalogue Part 5.6 and Part 15): the sensor between the arm's flange
(outer ring A) and the gripper (inner ring B) carries the wrench on spokes instrumented with
strain gauges. A gauge's resistance changes with its strain ε by the gauge factor K,
ΔR/R = K ε (7.8), and its Wheatstone bridge, one active arm, gives
ΔV = V ΔR / (4R + 2ΔR) ≈ V K ε / 4 (7.9) for a supply V. Linear in the wrench, the n bridge
outputs are V = H F (7.10), H (n, 6) the calibration matrix, and the wrench is recovered by
least squares, F = H^S V with H^S = (HᵀH)⁻¹Hᵀ (7.11), which needs n >= 6 and H of rank 6.

Geometry of the default H (a Maltese-cross sensor, the book's fig. 7.25; assumptions, ext.).
The sensor frame {S} has its origin at the hub's centre, where F = (f_x, f_y, f_z, m_x, m_y,
m_z) [N, N m] is expressed, z along the wrist axis. Four identical spokes lie along +x, +y,
-x, -y (φ_k = k π/2, k = 0..3; radial unit r_k = (cos φ_k, sin φ_k, 0), tangential
e_k = (-sin φ_k, cos φ_k, 0)) and each carries its load to the ring at the radius ρ
(``spoke_radius``). A spoke transmits a tangential shear t_k and an axial shear z_k (no radial
force: the flexures at the ring are radially compliant), so that the hub is in equilibrium,

    f = Σ t_k e_k + z_k ẑ,    m = Σ ρ r_k × (t_k e_k + z_k ẑ);

with equally stiff spokes the loads are the minimum-norm ones,

    t_k = (-f_x sin φ_k + f_y cos φ_k) / 2 + m_z / (4 ρ),
    z_k = f_z / 4 + (m_x sin φ_k - m_y cos φ_k) / (2 ρ).

Two gauges per spoke: gauge 2k on a side face reads the in-plane bending of t_k, gauge 2k + 1 on
the top face the out-of-plane bending of z_k. A shear s bends the spoke at its gauge to the
strain ε = c s (c = ℓ / (E W): lever arm to the ring over Young's modulus times the section
modulus; ``strain_per_newton``). An amplifier of gain G follows each bridge, so that

    H = G V K c / 4 · [t; z](F)    [V/N for the forces, V/(N m) for the torques].

The relative error of the linearised bridge, K ε / 2, is 0.1 % at 1000 µε with K = 2: the model
keeps the book's linear (7.10). A calibration matrix may also be given (any n >= 6 gauges, e.g.
a maker's calibration sheet): it replaces the geometry and its terms.

A reading adds white Gaussian noise of σ [V] (``noise_stddev``) per gauge at the converter's
input, then converts with an ADC of b bits over ±R [V]: the code rint(v / q), q = 2R / 2^b,
clipped to the two's-complement codes [-2^(b-1), 2^(b-1) - 1], times q; b = 0 leaves the value
unquantised, clipped to ±R. A clipped gauge is *saturated*, and the wrench recovered from it is
wrong.
"""

from dataclasses import dataclass
import math
from typing import Any, Mapping, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray
from robotica_kin.parameter_specs import ParameterSpec, seed_spec
from robotica_sim.sensors.preset_terms import params_from_parameters, preset_term_specs

__all__ = ['FT_PARAMETERS', 'FT_PRESETS', 'FT_TERMS', 'FtReading', 'FtSensorModel',
           'FtSensorParams', 'bridge_gain', 'calibrate', 'ft_sensor_params', 'ft_term_specs',
           'maltese_cross_matrix', 'pseudo_inverse']

SPOKES = 4             # spokes of the Maltese cross
MAX_CONDITION = 1e12   # a calibration matrix worse conditioned than this is refused as rank < 6


@dataclass(frozen=True)
class FtSensorParams:
    """
    Geometry, bridges and converter of a wrist F/T sensor; defaults: ideal (no noise, no ADC).

    Raises ValueError naming the term for a non-finite value, ρ, c, V or G <= 0, K = 0,
    σ < 0, bits outside 0..32 or R <= 0 (inf: no saturation).

    >>> FtSensorParams(gauge_factor=-12.0).gauge_factor   # nickel, book (7.8)
    -12.0
    """

    spoke_radius: float = 0.02        # ρ [m]: axis to where a spoke's load reaches the ring
    strain_per_newton: float = 4e-6   # c [1/N]: bending strain at a gauge per N of shear
    gauge_factor: float = 2.0         # K [-]: (ΔR/R)/(Δl/l), book (7.8)
    bridge_voltage: float = 5.0       # V [V]: bridge supply, book (7.9)
    amplifier_gain: float = 1.0       # G [-]: bridge amplifier
    noise_stddev: float = 0.0         # σ [V]: white noise per gauge at the ADC input
    adc_bits: int = 0                 # b [-]: ADC resolution, 0: none
    adc_range: float = math.inf       # R [V]: ADC input span ±R; beyond it a gauge saturates

    def __post_init__(self) -> None:
        for name in ('spoke_radius', 'strain_per_newton', 'bridge_voltage', 'amplifier_gain'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f'{name} must be finite and > 0, got {value!r}')
        if not (math.isfinite(self.gauge_factor) and self.gauge_factor != 0.0):
            raise ValueError(f'gauge_factor must be finite and not 0, got {self.gauge_factor!r}')
        if not (math.isfinite(self.noise_stddev) and self.noise_stddev >= 0.0):
            raise ValueError(f'noise_stddev must be finite and >= 0 V, got '
                             f'{self.noise_stddev!r}')
        if isinstance(self.adc_bits, bool) or not isinstance(self.adc_bits, int) \
                or not 0 <= self.adc_bits <= 32:
            raise ValueError(f'adc_bits must be an integer in [0, 32], got {self.adc_bits!r}')
        if not self.adc_range > 0.0:   # inf allowed: no saturation
            raise ValueError(f'adc_range must be > 0 V (inf: none), got {self.adc_range!r}')

    @property
    def adc_step(self) -> float:
        """Return the ADC quantum q = 2R / 2^b [V] (0 without quantisation)."""
        return 2.0 * self.adc_range / 2 ** self.adc_bits if self.adc_bits else 0.0


# Sensors. The book gives the gauge factors of (7.8) (chromium 2.5, manganese 0.5, platinum
# 4.8, nickel -12; semiconductor gauges about 100 times more sensitive) and no dimensions:
# every other value is an assumption (ext.), of the order of a small commercial six-axis sensor
# (rated about ±500 N and ±10 N m, at some 1000 µε in a metal spoke; noise about 0.1 N).
FT_PRESETS: dict[str, FtSensorParams] = {
    # Metal-foil gauges (constantan, K = 2.0, ext.), 1000 µε at 250 N of shear on a spoke.
    'metal_foil': FtSensorParams(
        spoke_radius=0.02, strain_per_newton=4e-6, gauge_factor=2.0, bridge_voltage=5.0,
        amplifier_gain=500.0, noise_stddev=1e-3, adc_bits=16, adc_range=10.0),
    # Silicon gauges (K = 120, ext.; book: about 100 times a metal gauge) on stiffer spokes,
    # 100 µε at 250 N, with a tenth of the amplification and less amplified noise (ext.).
    'semiconductor': FtSensorParams(
        spoke_radius=0.02, strain_per_newton=4e-7, gauge_factor=120.0, bridge_voltage=5.0,
        amplifier_gain=50.0, noise_stddev=3e-4, adc_bits=16, adc_range=10.0),
}
"""F/T sensors by name; values and sources in the comments of the source."""

_DEFAULT = FT_PRESETS['metal_foil']

FT_TERMS: dict[str, ParameterSpec] = {
    'spoke_radius': ParameterSpec(_DEFAULT.spoke_radius, 'Spoke radius rho [m]: sensor axis to '
                                  "where a spoke's load reaches the ring; assumption (ext.)",
                                  1e-3, 1.0),
    'strain_per_newton': ParameterSpec(_DEFAULT.strain_per_newton, 'Bending strain c [1/N] at '
                                       'a gauge per N of shear on its spoke; assumption (ext.)',
                                       1e-10, 1e-2),
    'gauge_factor': ParameterSpec(_DEFAULT.gauge_factor, 'Gauge factor K [-], (7.8): chromium '
                                  '2.5, platinum 4.8, nickel -12, semiconductor ~100x; not 0',
                                  -1000.0, 1000.0),
    'bridge_voltage': ParameterSpec(_DEFAULT.bridge_voltage, 'Bridge supply V [V], (7.9); '
                                    'assumption (ext.)', 1e-3, 100.0),
    'amplifier_gain': ParameterSpec(_DEFAULT.amplifier_gain, 'Bridge amplifier gain G [-]; '
                                    'assumption (ext.)', 1e-3, 1e6),
    'noise_stddev': ParameterSpec(_DEFAULT.noise_stddev, 'White noise sigma [V] per gauge at '
                                  'the ADC input; assumption (ext.)', 0.0, 100.0),
    'adc_bits': ParameterSpec(_DEFAULT.adc_bits, 'ADC resolution b [bits], 0: none; '
                              'assumption (ext.)', 0, 32),
    'adc_range': ParameterSpec(_DEFAULT.adc_range, 'ADC input span +-R [V]: a gauge beyond it '
                               'saturates; assumption (ext.)', 1e-3, 1e3),
}
"""The terms of :class:`FtSensorParams` as node parameters, at the default preset's values."""

FT_PARAMETERS: dict[str, ParameterSpec] = {
    'preset': ParameterSpec('metal_foil', 'F/T sensor: the starting values of the terms (a term '
                            'given explicitly overrides it)', choices=tuple(FT_PRESETS)),
    'seed': seed_spec('Seed of the gauge noise draws'),
    **FT_TERMS,
}
"""The F/T sensor emulator node's parameters by name: :func:`ft_sensor_params`."""


def ft_term_specs(preset: str) -> dict[str, ParameterSpec]:
    """
    Return :data:`FT_TERMS` with the values of the sensor ``preset`` as their defaults.

    Raises ParameterError for an unknown preset.

    >>> ft_term_specs('semiconductor')['gauge_factor'].default
    120.0
    """
    return preset_term_specs(FT_TERMS, FT_PRESETS, FT_PARAMETERS['preset'], preset)


def ft_sensor_params(parameters: Mapping[str, Any]) -> FtSensorParams:
    """
    Return the sensor of the emulator node's ``parameters`` (names of FT_PARAMETERS).

    The ``preset`` gives every term; a term in ``parameters`` replaces its value. Raises
    :class:`~robotica_kin.parameter_specs.ParameterError` naming the parameter for a value out
    of its range or choices, or refused by :class:`FtSensorParams`.

    >>> ft_sensor_params({'preset': 'metal_foil', 'adc_bits': 12}).adc_bits
    12
    """
    return params_from_parameters(parameters, FT_PARAMETERS, FT_TERMS, FT_PRESETS)


def bridge_gain(params: FtSensorParams) -> float:
    """
    Return the amplified bridge output per unit strain, G V K / 4 [V], book (7.8)-(7.9).

    One active arm, linearised: ΔV ≈ V ΔR / (4R) with ΔR/R = K ε.

    >>> bridge_gain(FtSensorParams(gauge_factor=2.5, bridge_voltage=10.0, amplifier_gain=100.0))
    625.0
    """
    return params.amplifier_gain * params.bridge_voltage * params.gauge_factor / 4.0


def _equilibrium_matrix(spoke_radius: float) -> NDArray[np.float64]:
    """Return A (6, 8): the wrench at the hub of unit loads t_k (column 2k), z_k (2k + 1)."""
    columns = []
    for k in range(SPOKES):
        c, s = math.cos(k * math.pi / 2.0), math.sin(k * math.pi / 2.0)
        columns.append([-s, c, 0.0, 0.0, 0.0, spoke_radius])                   # t_k e_k
        columns.append([0.0, 0.0, 1.0, spoke_radius * s, -spoke_radius * c, 0.0])   # z_k ẑ
    return np.array(columns).T


def maltese_cross_matrix(params: FtSensorParams) -> NDArray[np.float64]:
    """
    Return the calibration matrix H (8, 6) of the Maltese-cross geometry [V/N, V/(N m)].

    H = G V K c / 4 · A⁺ with A (6, 8) the hub's equilibrium under the spoke loads and A⁺ its
    minimum-norm inverse (module docstring); rows: gauges 2k (side, t_k) and 2k + 1 (top, z_k)
    of spoke k; columns: f_x, f_y, f_z, m_x, m_y, m_z.

    >>> H = maltese_cross_matrix(FtSensorParams(strain_per_newton=1.0, bridge_voltage=2.0))
    >>> H[0].round(3).tolist()   # gauge 0 (spoke +x, side) reads f_y / 2 + m_z / (4 ρ)
    [0.0, 0.5, 0.0, 0.0, 0.0, 12.5]
    """
    shares = np.linalg.pinv(_equilibrium_matrix(params.spoke_radius))
    return np.asarray(bridge_gain(params) * params.strain_per_newton * shares,
                      dtype=np.float64)


def _calibration_matrix(value: ArrayLike) -> NDArray[np.float64]:
    """Return ``value`` as a read-only H (n, 6), n >= 6, of rank 6, or raise ValueError."""
    try:
        matrix = np.array(value, dtype=np.float64)
    except (TypeError, ValueError) as err:
        raise ValueError(f'calibration_matrix must be numbers of shape (n, 6), got {value!r}') \
            from err
    if matrix.ndim != 2 or matrix.shape[1] != 6 or matrix.shape[0] < 6:
        raise ValueError('calibration_matrix must have shape (n, 6) with n >= 6 gauges, got '
                         f'shape {matrix.shape}')
    if not np.isfinite(matrix).all():
        raise ValueError('calibration_matrix must be finite')
    if np.linalg.cond(matrix) > MAX_CONDITION:
        raise ValueError('calibration_matrix must have rank 6 (independent columns): '
                         'no wrench can be recovered from it')
    matrix.setflags(write=False)
    return matrix


def pseudo_inverse(calibration_matrix: ArrayLike) -> NDArray[np.float64]:
    """
    Return H^S = (HᵀH)⁻¹Hᵀ (6, n), book (7.11), of a calibration matrix H (n, 6).

    Computed by SVD (``numpy.linalg.pinv``), equal to the book's form for H of rank 6. Raises
    ValueError unless H is finite, (n, 6) with n >= 6, and of rank 6.

    >>> pseudo_inverse(np.vstack([np.eye(6), np.eye(6)]))[0].tolist()   # two gauges a wrench
    [0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0]
    """
    matrix = _calibration_matrix(calibration_matrix)
    return np.asarray(np.linalg.pinv(matrix), dtype=np.float64)


def calibrate(wrenches: ArrayLike, readings: ArrayLike) -> NDArray[np.float64]:
    """
    Return the calibration matrix H (n, 6) that least-squares fits known wrenches to readings.

    The book's calibration with known wrenches: each row of ``wrenches`` (m, 6) [N, N m] was
    applied and read as the row of ``readings`` (m, n) [V]; V = H F (7.10) for every row is
    ``readings = wrenches Hᵀ``, solved for Hᵀ by least squares. Exact for m = 6 independent
    wrenches without noise; more wrenches average the noise. Raises ValueError for non-finite
    values, mismatched rows, or wrenches that do not span the six axes (m < 6 or rank < 6).

    >>> H = np.arange(48.0).reshape(8, 6) ** 0.5
    >>> W = np.vstack([np.eye(6), np.ones((1, 6))])
    >>> bool(np.allclose(calibrate(W, W @ H.T), H))
    True
    """
    w = np.asarray(wrenches, dtype=np.float64)
    v = np.asarray(readings, dtype=np.float64)
    if w.ndim != 2 or w.shape[1] != 6:
        raise ValueError(f'wrenches must have shape (m, 6), got shape {w.shape}')
    if v.ndim != 2 or v.shape[0] != w.shape[0]:
        raise ValueError(f'readings must have shape (m, n) with m = {w.shape[0]} rows, got '
                         f'shape {v.shape}')
    if not (np.isfinite(w).all() and np.isfinite(v).all()):
        raise ValueError('wrenches and readings must be finite')
    if w.shape[0] < 6 or np.linalg.cond(w) > MAX_CONDITION:
        raise ValueError(f'wrenches must span the six axes (rank 6), got {w.shape[0]} of rank '
                         f'{np.linalg.matrix_rank(w)}')
    transposed, *_ = np.linalg.lstsq(w, v, rcond=None)
    return np.ascontiguousarray(transposed.T)


class FtReading(NamedTuple):
    """One reading (or m readings) of the sensor: gauge volts, recovered wrench, saturation."""

    volts: NDArray[np.float64]      # V (n,) or (m, n) [V]: the gauges after the ADC
    wrench: NDArray[np.float64]     # F̂ = H^S V (6,) or (m, 6) [N, N m], book (7.11)
    saturated: NDArray[np.bool_]    # (n,) or (m, n): gauges clipped at the ADC's span


class FtSensorModel:
    """
    A wrist F/T sensor: true wrench -> gauge volts -> recovered wrench (module docstring).

    Each reading draws n standard normals (one a gauge) from the model's own generator, so
    :meth:`measure` called m times and :meth:`measure_many` on m wrenches read the same.

    Parameters
    ----------
    params : FtSensorParams
        Geometry, bridges and converter.
    seed : int or numpy.random.Generator
        Seed of the model's generator, or a generator to draw from (then shared).
    calibration_matrix : array_like (n, 6), optional
        H [V/N, V/(N m)], n >= 6 gauges, of rank 6; default: :func:`maltese_cross_matrix`.

    Examples
    --------
    >>> ft = FtSensorModel(FtSensorParams(), seed=0)
    >>> ft.measure([10.0, 0.0, -20.0, 0.0, 0.5, 0.0]).wrench.round(12).tolist()
    [10.0, 0.0, -20.0, 0.0, 0.5, 0.0]

    """

    def __init__(self, params: FtSensorParams, seed: int | np.random.Generator,
                 calibration_matrix: ArrayLike | None = None) -> None:
        if not isinstance(params, FtSensorParams):
            raise ValueError(f'params must be FtSensorParams, got {type(params).__name__}')
        self._params = params
        self._given = None if calibration_matrix is None else \
            _calibration_matrix(calibration_matrix)
        self._rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
        self._set_matrix()

    def _set_matrix(self) -> None:
        self._matrix = self._given if self._given is not None else \
            _calibration_matrix(maltese_cross_matrix(self._params))
        self._inverse = pseudo_inverse(self._matrix)

    @property
    def params(self) -> FtSensorParams:
        """Return the geometry, bridges and converter."""
        return self._params

    @params.setter
    def params(self, params: FtSensorParams) -> None:
        """Change the terms from the next reading on (H too, unless it was given)."""
        if not isinstance(params, FtSensorParams):
            raise ValueError(f'params must be FtSensorParams, got {type(params).__name__}')
        self._params = params
        self._set_matrix()

    @property
    def calibration_matrix(self) -> NDArray[np.float64]:
        """Return H (n, 6) [V/N, V/(N m)], read-only, book (7.10)."""
        return self._matrix

    @property
    def gauges(self) -> int:
        """Return n, the number of strain gauges: the rows of H."""
        return self._matrix.shape[0]

    def wrench_covariance(self) -> NDArray[np.float64]:
        """
        Return the covariance (6, 6) [N², N² m, N² m²] of the recovered wrench, unsaturated.

        H^S (σ² + q²/12) I H^Sᵀ: the gauge noise and the ADC's quantisation noise (uniform over
        one step, which holds for σ of about q or more) through (7.11).
        """
        p = self._params
        variance = p.noise_stddev ** 2 + p.adc_step ** 2 / 12.0
        return variance * self._inverse @ self._inverse.T

    def _convert(self, volts: NDArray[np.float64]) -> tuple[NDArray[np.float64],
                                                            NDArray[np.bool_]]:
        """Return the ADC's output [V] of ``volts`` and which of them saturated."""
        p = self._params
        if p.adc_bits == 0:
            return np.clip(volts, -p.adc_range, p.adc_range), np.abs(volts) > p.adc_range
        codes = np.rint(volts / p.adc_step)
        low, high = -2.0 ** (p.adc_bits - 1), 2.0 ** (p.adc_bits - 1) - 1.0
        return np.clip(codes, low, high) * p.adc_step, (codes < low) | (codes > high)

    def measure_many(self, wrenches: ArrayLike) -> FtReading:
        """
        Return the readings of the true wrenches ``wrenches`` (m, 6) [N, N m] in {S}.

        V = adc(H F + n) per row, F̂ = H^S V (module docstring); arrays of m rows. Raises
        ValueError for a non-finite wrench or a shape other than (m, 6).
        """
        f = np.asarray(wrenches, dtype=np.float64)
        if f.ndim != 2 or f.shape[1] != 6:
            raise ValueError(f'wrenches must have shape (m, 6), got shape {f.shape}')
        if not np.isfinite(f).all():
            raise ValueError('wrenches must be finite')
        noise = self._params.noise_stddev * self._rng.standard_normal((f.shape[0], self.gauges))
        volts, saturated = self._convert(f @ self._matrix.T + noise)
        return FtReading(volts, volts @ self._inverse.T, saturated)

    def measure(self, wrench: ArrayLike) -> FtReading:
        """
        Return the reading of the true wrench ``wrench`` (6,) [N, N m], in the sensor frame {S}.

        Raises ValueError for a non-finite wrench or a shape other than (6,).
        """
        f = np.asarray(wrench, dtype=np.float64)
        if f.shape != (6,):
            raise ValueError(f'wrench must have shape (6,), got shape {f.shape}')
        volts, wrench_hat, saturated = self.measure_many(f[None, :])
        return FtReading(volts[0], wrench_hat[0], saturated[0])
