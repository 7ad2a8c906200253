"""Independent recording generator for the phantom + passive knee exoskeleton rig (docs/rig.md §1).

It imports nothing from exobench beyond itself (a test keeps it so): the open-world validation
needs recordings whose mechanics share no code with the analysis. Its modules by what they write:
:mod:`.rig` (the nominal rig and the violations), :mod:`.leg` (the hexapod's motion, the leg's
equations of motion and the markers), :mod:`.chain` (the exoskeleton's series chain solver),
:mod:`.cells` (load cells and SYNC), :mod:`.c3d` (the C3D writer), :mod:`.study` (trials and
the manifest).

Writes the raw files a lab would write (one C3D per spring and ``manifest.csv``) from the rig
contract and the physics alone: the hexapod drives the knee kinematically along the measured
mean cycle with per-stride peak/valley shifts, the clutched exoskeleton transmits one moment
through interface → bars → frame → play → spring side, and the ankle load cells record the
hexapod's force on the ankle from the two-link leg's equations of motion.

A recording can violate any relaxation of docs/assumptions.md: ``violations`` maps a term key
``row.family`` to {parameter: value} (``VIOLATIONS`` lists them, ``REQUIRES`` their needs). The
laws are written here from each relaxation's one-line law and the rig contract:

- Chain (limb → interface δ → bars → frame ε → play → spring side s, all in knee rotation, one
  moment M through them): the interface and the frame are each k(t)·(x + β·x³) + c·ẋ + τ·sign ẋ
  = M, the friction in parallel with the spring (x sticks while |M − k(t)(x + βx³)| ≤ τ), with
  k(t) = k·(1 + ρ·t); a present ``*.elastic`` makes the element compliant. The spring side is
  M_s = n·(r·F − max(r·F0 + k_t·n·s, 0)) with F = F0 + k(t)·x·(1 + a·|x|) + c·ẋ, x = r·n·s,
  pulling through the cable while F > 0 (the |x| keeps the law monotone below the pretension
  point); its friction τ (chain and clutch) sticks s while |M − M_s| ≤ τ; the tensioner, like
  the chain, cannot push. Play p: the chain pulls only once the knee has turned p since the
  engagement (M ≥ 0). The straps' play p: the bars turn freely within a dead band
  b ∈ [−p/2, p/2] about the phantom's segments (b adds to δ) and carry M only at an end of it
  (M > 0 at +p/2, M < 0 at −p/2); unloaded, b is what leaves the chain's zero-moment state in
  place, and it stays put while the clutch is free. Implicit Euler at the sub-stepped rate, the
  nearest root from the last state (a snap where the tensioner's negative stiffness outweighs a
  soft interface or frame).
- Leg: Newton–Euler with the real segments (the analysis keeps the rig's), the ankle on the
  vertical line o anterior of the hip, the phantom knee's own extensor moment
  k·θ + c·θ̇ + τ·sign θ̇ beside M, the hip's moment −(c·φ̇1 + τ·sign φ̇1 + k·φ1) on the thigh. The
  hexapod is programmed so that the knee follows the mean cycle whatever the real geometry.
- Load cells: each records g·N(its true force + s·the other true force)(t·(1 − ε) − d − D)
  + o + ḃ·t + noise, N(F) = F·(1 + q·|F|) with F in kN, t the stamp since the trial's first
  sample; the ankle cells' true force is their share of F_y·cos α + F_x·sin α, their crosstalk
  a share of the spring's tension, the spring cell's a share of the vertical ankle force F_y;
  the analog clock's lag D and rate error ε also move SYNC.
- Between trials: z_i ~ N(0, 1) per trial (truncated at ±3, from a stream of the seed apart from
  the noise's), trial i's interface stiffness k·(1 + s·z_i) and LC_SPRING's zero s·z_i; each
  Trial reports its draws (``Trial.between``).
- Markers follow the real geometry; the thigh bar (and the spring on it) is turned by a about
  the hinge; the knee markers sit o anterior of the axis, on the thigh.

Sign conventions: X anterior, Y up, Z lateral; knee flexion θ positive; an extensor moment M
is positive (it acts counter-clockwise about +Z on the shank and clockwise on the thigh).
"""

from .chain import ExoResponse, exoskeleton_response
from .leg import KneeMotion, Leg, ankle_forces, ankle_vertical_force, real_leg
from .rig import (
    BETWEEN,
    CHANNELS,
    MANIFEST_COLUMNS,
    MARKERS,
    REQUIRES,
    VIOLATIONS,
    checked_violations,
)
from .study import Trial, simulate_study, write_study

__all__ = [
    "BETWEEN",
    "CHANNELS",
    "MANIFEST_COLUMNS",
    "MARKERS",
    "REQUIRES",
    "VIOLATIONS",
    "ExoResponse",
    "KneeMotion",
    "Leg",
    "Trial",
    "ankle_forces",
    "ankle_vertical_force",
    "checked_violations",
    "exoskeleton_response",
    "real_leg",
    "simulate_study",
    "write_study",
]
