"""Vectorised path cost over sampled populations ``(P, S, 3)`` (document 002 eq. 9, corrected).

``W = w_L Pc + w_S Sc + w_E Ec``:

* **Pc**, length (eqs. 10–11): sum of segment lengths (m).
* **Sc**, terrain and constraint cost (eq. 12): the document charges M per
  sample below the seabed.  auvplan checks every *segment* exactly
  (:meth:`Terrain.segment_min_altitude`, so nothing dips under the seabed
  between samples) against the minimum altitude, and the other constraints
  (depth limits, bounds, static obstacles) at the samples and with the
  obstacles' segment tests.  Each violating segment costs M and every metre
  of violation depth ``violation_slope`` more, which gives the search a slope
  towards feasibility.
* **Ec**, energy in the current field, per segment with the current at its
  midpoint, track tangent ŝ, c∥ = c·ŝ and c⊥ = |c - c∥ ŝ|:

  - ``"physical"`` (default): ground speed V_g = c∥ + √(V² - c⊥²) (the vehicle
    crabs to hold the track), time ds / V_g, energy (P_hotel + k V³) ds / V_g;
    infeasible where V < c⊥ or V_g ≤ 0.  Reported in joules and converted to
    cost units by ``energy_scale`` (default: metres of still-water travel per
    joule, V / (P_hotel + k V³), so that the term reads as "equivalent metres").
  - ``"document"``: eqs. 16–17 as written, |V_h| = √(V² - (V_oc sin Φ)²) +
    V_oc cos Φ and W = ρ |V_h|³ ds / V_oc with V_oc the current speed (not
    physical: it cubes the ground speed, divides by the current — floored at
    1 mm/s — and prefers head currents; docs/methods.md §2).
  - ``"document-vehicle"``: eq. 17 with the document's own gloss of V_oc under it, the
    vehicle's still-water speed: W = ρ |V_h|³ ds / V (the ground speed |V_h| as above, with the
    current; only the divisor is the constant V, so still water is finite: ρ V² ds).

The currents at all midpoints come from the field in one vectorised call; everything else is one
compiled pass (:func:`auvplan.runtime.jit.kernel`) over the segments of the population that sums every
term per path, so a population of 50 paths × 200 samples costs about a third of a millisecond.

The package, one idea a module: :mod:`.model` (the cost model's settings and the per-path terms),
:mod:`.energy` (a segment's energy in the current: the compiled kernel and its vectorised front) and
:mod:`.paths` (the constraint terms and the one compiled pass over a population: :func:`evaluate_paths`).
"""

from __future__ import annotations

from .energy import energy_kernel, segment_energy
from .model import ENERGY_READINGS, CostModel, CostRow, CostTerms, energy_mode, propulsion_power
from .paths import evaluate_paths

__all__ = ["CostModel", "CostTerms", "CostRow", "evaluate_paths", "segment_energy", "energy_kernel",
           "propulsion_power", "ENERGY_READINGS", "energy_mode"]
