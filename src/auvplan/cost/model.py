"""The path cost's settings and per-path terms: weights, vehicle figures, the energy reading (:mod:`auvplan.cost`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TypedDict

from .._types import BoolArray, FloatArray, IntArray

__all__ = ["ENERGY_READINGS", "CostModel", "energy_mode", "propulsion_power", "CostRow", "CostTerms"]


ENERGY_READINGS = ("physical", "document", "document-vehicle")
"""The energy models (module notes): physical, and document 002's eq. 17 with V_oc the current's
speed (as written) or the vehicle's still-water speed (the document's gloss under eq. 17)."""


@dataclass(frozen=True)
class CostModel:
    """Weights and vehicle figures of the path cost.

    Attributes
    ----------
    speed : float
        Through-water speed V (m/s).
    hotel_power, drag_k : float
        P_hotel (W) and k (W s³/m³) of the power model P = P_hotel + k V³.
    energy : str
        ``"physical"``, ``"document"`` or ``"document-vehicle"`` (:data:`ENERGY_READINGS`).
    w_length, w_terrain, w_energy : float
        Term weights.
    terrain_penalty : float
        M, cost of one violating segment.
    violation_slope : float
        Cost per metre of violation depth.
    energy_scale : float
        Cost units per joule (physical) or per unit of the document's energy; 0 = auto.

    Raises
    ------
    ValueError
        If the speed is not positive or ``energy`` is not one of the two models.
    """

    speed: float = 1.5
    hotel_power: float = 15.0
    drag_k: float = 5.8
    energy: str = "physical"
    w_length: float = 1.0
    w_terrain: float = 1.0
    w_energy: float = 1.0
    terrain_penalty: float = 1.0e4
    violation_slope: float = 100.0
    energy_scale: float = 0.0

    def __post_init__(self) -> None:
        if not self.speed > 0:
            raise ValueError(f"speed must be positive, got {self.speed}")
        if self.energy not in ENERGY_READINGS:
            raise ValueError(f"energy must be one of {', '.join(map(repr, ENERGY_READINGS))}, got {self.energy!r}")

    @property
    def scale(self) -> float:
        """Energy-to-cost conversion in force.

        Returns
        -------
        float
            ``energy_scale`` when set, else V / (P_hotel + k V³) (cost units per joule, physical) or
            1 / V² (both document readings).
        """
        if self.energy_scale > 0:
            return self.energy_scale
        if self.energy == "physical":
            return self.speed / (self.hotel_power + self.drag_k * self.speed**3)
        return 1.0 / self.speed**2  # document: |V_h|³/V_oc ~ V² per metre (1 m/s current, or V_oc = V)


def energy_mode(model: CostModel) -> int:
    """The compiled kernels' code of the model's energy reading.

    Parameters
    ----------
    model : CostModel
        Its ``energy``.

    Returns
    -------
    int
        0 physical, 1 document (V_oc the current's speed), 2 document-vehicle (V_oc = V).
    """
    return ENERGY_READINGS.index(model.energy)


def propulsion_power(model: CostModel) -> float:
    """Electrical power at the model's speed.

    Parameters
    ----------
    model : CostModel
        Speed and power model.

    Returns
    -------
    float
        Hotel load + drag_k · V³ (W).
    """
    return float(model.hotel_power + model.drag_k * model.speed**3)


class CostRow(TypedDict):
    """The cost terms of one path as plain numbers (:meth:`CostTerms.row`); units as in :class:`CostTerms`."""

    total: float
    length: float
    terrain: float
    energy: float
    energy_j: float
    duration_s: float
    violations: int
    min_clearance_m: float


@dataclass(frozen=True, eq=False)
class CostTerms:
    """Per-path cost terms (arrays of shape ``(P,)``).

    Parameters
    ----------
    total : numpy.ndarray
        Weighted cost ``W = w_L Pc + w_S Sc + w_E Ec`` (cost units).
    length : numpy.ndarray
        Path length Pc (m).
    terrain : numpy.ndarray
        Constraint cost Sc: ``M`` per violating segment plus ``violation_slope`` per metre of violation.
    energy : numpy.ndarray
        Energy term Ec in cost units (``energy_j`` or the document's energy times :attr:`CostModel.scale`).
    energy_j : numpy.ndarray
        Physical propulsion and hotel energy (J).
    duration_s : numpy.ndarray
        Travel time (s).
    violations : numpy.ndarray
        Violating segments per path (int).
    min_clearance : numpy.ndarray
        Smallest geometric clearance: altitude above the seabed or distance to a static obstacle (m).
    """

    total: FloatArray
    length: FloatArray
    terrain: FloatArray
    energy: FloatArray
    energy_j: FloatArray
    duration_s: FloatArray
    violations: IntArray
    min_clearance: FloatArray
    """Smallest geometric clearance: altitude above the seabed or distance to a static obstacle (m)."""

    @property
    def feasible(self) -> BoolArray:
        """Where no segment violates a constraint and the current never beats the vehicle.

        Returns
        -------
        numpy.ndarray of bool
            ``(P,)``.
        """
        feasible: BoolArray = self.violations == 0
        return feasible

    def row(self, i: int) -> CostRow:
        """The terms of one path as plain numbers.

        Parameters
        ----------
        i : int
            Path index.

        Returns
        -------
        CostRow
            ``total``, ``length``, ``terrain``, ``energy``, ``energy_j``, ``duration_s``,
            ``violations`` and ``min_clearance_m``.
        """
        return {
            "total": float(self.total[i]),
            "length": float(self.length[i]),
            "terrain": float(self.terrain[i]),
            "energy": float(self.energy[i]),
            "energy_j": float(self.energy_j[i]),
            "duration_s": float(self.duration_s[i]),
            "violations": int(self.violations[i]),
            "min_clearance_m": float(self.min_clearance[i]),
        }
