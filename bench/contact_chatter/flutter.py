#!/usr/bin/env python3
"""Flutter of the leading wheelset at its FASTSIM quasi-static state (docs/theory_flange_chatter.md,
section 9): reproduces every number of that section.

    cmake --build build --target study_linear_modes
    RAILDYN_BUILD_DIR=build python3 bench/contact_chatter/flutter.py [--swap] [--t 15]

1. (--swap, ~3 CPU min) law swap: FASTSIM run to T, continued with Polach, and the reverse;
   per wheelset the share of samples (0.5 ms) with a wheel without contact in T..T+2 s.
2. FASTSIM's own quasi-static state: the deck with normal contact damping (4e6 N s/m) run to T,
   its state averaged over 0.1 s (the damped run still oscillates, with ~20 um amplitude).
3. Linearisation (study_linear_modes, central differences) at that state and at Polach's state
   at T, dumped; for wheelset 1 the least damped modes as computed, with its (y, z, roll)
   stiffness block symmetrised (the circulatory part removed), with its damping block zeroed,
   with the circulatory part scaled (the threshold), with the wheelsets' height and roll
   condensed out (quasi-static normal contact), and at the same FASTSIM state with normal
   contact damping (4e6 N s/m) and with the friction coefficient 0 and 1 (same pose: how the
   circulatory part scales with friction).
Decks are written into a temporary directory; they include the repository's acceptance deck.
"""
import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))
import raildyn  # noqa: E402

WHEELSETS = ("w1", "w2", "w3", "w4")
WS1_MASS = np.diag([1813.0, 1813.0, 1813.0, 1120.0, 1120.0, 112.0])   # x y z yaw roll spin (vehicle deck)


def write_deck(tmp: Path, name: str, wheelset_extra: str) -> Path:
    text = f"&include file = '{ROOT / 'inputs' / 'manchester_v1_tc1_elastic.nml'}' /\n"
    if wheelset_extra:
        text += "".join(f"&wheelset name = '{w}', {wheelset_extra} /\n" for w in WHEELSETS)
    path = tmp / f"{name}.nml"
    path.write_text(text)
    return path


def state_at(deck: Path, t: float, mean_over: float = 0.0, dt: float = 1e-4) -> np.ndarray:
    """[t, y...] at t, or the state averaged over [t, t + mean_over] (samples every dt)."""
    with raildyn.Model.from_file(deck) as m:
        m.initialize(write_output=False)
        m.advance(t)
        if mean_over <= 0:
            return np.concatenate([[t], m.state()])
        ys, tk = [], t
        for _ in range(int(round(mean_over / dt))):
            tk += dt
            m.advance(tk)
            ys.append(m.state())
        return np.concatenate([[t + 0.5 * mean_over], np.mean(ys, axis=0)])


def swap(deck_a: Path, deck_b: Path, t0: float, span: float = 2.0, dt: float = 5e-4) -> None:
    y = state_at(deck_a, t0)
    with raildyn.Model.from_file(deck_b) as m:
        m.set_start(t0, y[1:])
        m.initialize(write_output=False)
        off = np.zeros(len(WHEELSETS))
        n, t = 0, t0
        while t < t0 + span - 1e-12:
            t += dt
            m.advance(t)
            n += 1
            for k, w in enumerate(WHEELSETS):
                sides = [m.output(f"wheelsets/{w}/{s}/wheel")[0] for s in ("left", "right")]
                off[k] += min(sides) == 0
    print(f"  {deck_a.stem} to {t0:g} s, then {deck_b.stem}: wheel without contact in "
          + ", ".join(f"{w} {100 * off[k] / n:.1f} %" for k, w in enumerate(WHEELSETS)))


def linearise(study: Path, deck: Path, state: np.ndarray, tmp: Path, tag: str):
    sfile, jfile = tmp / f"{tag}.state", tmp / f"{tag}.jac"
    np.savetxt(sfile, state[None, :])
    env = dict(os.environ, STUDY_STATE_FILE=str(sfile), STUDY_DUMP_JAC=str(jfile), STUDY_BLOCK_BODY="4")
    out = subprocess.run([str(study), str(deck), "1", "60"], env=env, check=True,
                         capture_output=True, text=True).stdout
    slots = next(line for line in out.splitlines() if line.startswith("free slots")).split(":")[1].split()
    lines = jfile.read_text().splitlines()
    return int(lines[0]), np.loadtxt(lines[1:]), np.array([int(s) - 1 for s in slots])


def least_damped(jac: np.ndarray, f_min: float = 60.0, count: int = 2) -> str:
    lam = np.linalg.eigvals(jac)
    lam = lam[lam.imag > 2 * np.pi * f_min]
    zeta = -lam.real / np.abs(lam)
    return ", ".join(f"{lam[k].imag / (2 * np.pi):.1f} Hz zeta {zeta[k]:+.3f}" for k in np.argsort(zeta)[:count])


def analyse(tag: str, nfree: int, jac: np.ndarray, slots: np.ndarray, full: bool) -> None:
    yzr = [1, 2, 4]
    rows, cols = nfree + slots[yzr], slots[yzr]
    m = WS1_MASS[np.ix_(yzr, yzr)]
    k = -m @ jac[np.ix_(rows, cols)]
    circ = 0.5 * (k - k.T)
    print(f"  {tag}: least damped {least_damped(jac)}; circulatory (K_yz - K_zy)/2 = {circ[0, 1]:.3g} N/m, "
          f"(K_z,roll - K_roll,z)/2 = {circ[1, 2]:.3g} N")
    if not full:
        return
    sym = jac.copy()
    sym[np.ix_(rows, cols)] = -np.linalg.solve(m, 0.5 * (k + k.T))
    print(f"    ws1 (y, z, roll) stiffness symmetrised: {least_damped(sym)}")
    undamped = jac.copy()
    undamped[np.ix_(nfree + slots, nfree + slots)] = 0
    print(f"    ws1 damping block zeroed:               {least_damped(undamped)}")
    print(f"    wheelsets' z and roll quasi-static:      {condensed(nfree, jac, slots)}")
    scan = []
    for alpha in np.arange(0.0, 1.01, 0.1):
        part = jac.copy()
        part[np.ix_(rows, cols)] = -np.linalg.solve(m, 0.5 * (k + k.T) + alpha * circ)
        scan.append(f"{alpha:.1f}: {least_damped(part, count=1).split(', ')[0].split('zeta ')[1]}")
    print("    circulatory part scaled by alpha, least damping ratio: " + "; ".join(scan))


def condensed(nfree: int, jac: np.ndarray, slots_ws1: np.ndarray, wheelsets: int = 4) -> str:
    """Quasi-static normal contact in the linear model: the height and roll of every wheelset
    (bodies 4-7, six slots each from wheelset 1's) follow from their force balance (their
    accelerations set to zero, the balance's velocity terms neglected), the rest keeps its
    dynamics; the least damped modes of the reduced system."""
    assert jac.shape[0] == 2 * nfree, "condensation written for scenes without element states"
    p = np.concatenate([slots_ws1[[2, 4]] + 6 * k for k in range(wheelsets)])
    o = np.setdiff1d(np.arange(nfree), p)
    jqq, jqv = jac[nfree:, :nfree], jac[nfree:, nfree:]
    s = -np.linalg.solve(jqq[np.ix_(p, p)], jqq[np.ix_(p, o)])
    a = np.zeros((2 * len(o), 2 * len(o)))
    a[:len(o), len(o):] = np.eye(len(o))
    a[len(o):, :len(o)] = jqq[np.ix_(o, o)] + jqq[np.ix_(o, p)] @ s
    a[len(o):, len(o):] = jqv[np.ix_(o, o)] + jqv[np.ix_(o, p)] @ s
    lam = np.linalg.eigvals(a)
    return f"{least_damped(a, f_min=0.5, count=3)}; highest {lam.imag.max() / (2 * np.pi):.0f} Hz"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t", type=float, default=15.0, help="time of the states [s]")
    ap.add_argument("--swap", action="store_true", help="also run the law-swap experiments")
    args = ap.parse_args()
    build = Path(os.environ.get("RAILDYN_BUILD_DIR", ROOT / "build"))
    study = build / "bench" / "study_linear_modes"
    if not study.exists():
        sys.exit(f"{study} missing: cmake --build {build} --target study_linear_modes")
    with tempfile.TemporaryDirectory() as tmpname:
        tmp = Path(tmpname)
        fastsim = write_deck(tmp, "fastsim", "")
        polach = write_deck(tmp, "polach", "creep_law = 'polach'")
        damped = write_deck(tmp, "fastsim_damped", "contact_damping = 4.0e6")
        if args.swap:
            print("1. law swap")
            swap(fastsim, polach, args.t)
            swap(polach, fastsim, args.t)
        print("2-3. linearisation (wheelset 1 = body 4)")
        s_fastsim = state_at(damped, args.t, mean_over=0.1)
        s_polach = state_at(polach, args.t)
        for tag, deck, state, full in (("FASTSIM at its own state", fastsim, s_fastsim, True),
                                       ("Polach at its own state", polach, s_polach, True),
                                       ("FASTSIM at Polach's state", fastsim, s_polach, False)):
            analyse(tag, *linearise(study, deck, state, tmp, tag.split()[0] + tag.split()[-2]), full)
        analyse("FASTSIM with contact_damping 4e6 N s/m, at FASTSIM's state",
                *linearise(study, damped, s_fastsim, tmp, "damped"), False)
        for mu in (0.0, 1.0):
            deck = write_deck(tmp, f"fastsim_mu{mu:g}", f"friction = {mu:g}")
            analyse(f"FASTSIM, friction {mu:g}, at FASTSIM's state", *linearise(study, deck, s_fastsim, tmp,
                                                                                 f"mu{mu:g}"), False)


if __name__ == "__main__":
    main()
