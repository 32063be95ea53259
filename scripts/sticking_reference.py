#!/usr/bin/python3
"""An independent reference for the flights of the single stop that sticks,
in arbitrary-precision arithmetic (mpmath): where a motion released from its
stop sticks again, computed far beyond double precision.

    scripts/sticking_reference.py --zeta Z --omega W [--sigma S] [--r R]
        [--digits 40] [--flights 1] [--json]

The model is configs/single-stop.toml's: x'' + 2 zeta x' + x = cos(omega t)
below the stop x = sigma, an impact reversing the velocity v -> -r v. Held at
the stop the mass is pressed into it while cos(omega t) > sigma, and released
from rest where cos(omega t) falls through sigma (omega t = arccos sigma, mod
2 pi): every flight starts from that one state. Between impacts the flow is
the closed form of the damped forced oscillator; an impact is the first time
the mass reaches the stop, found by sampling (steps of T/64, finer just after
an impact, growing back) and bisection to the working precision, a touch
between two samples by the local maximum of x. A chatter's impacts are
followed one by one until their speed falls below 10^-(digits/2) with the
force into the stop: the stick (the speeds of the last bounces are at the
working precision, the time of the stick well within it). For each flight it
prints how long it lasted in forcing periods T = 2 pi / omega, and in which
period, counted from the release's (periods start at t = kT), the stick
began: the index of the period that first holds the mass, not the orbit's
period, which also counts the periods held until the next release. A flight
whose result changes between 40 and 60 digits is beyond what either
resolves.
"""

import argparse
import json
import math
import sys

try:
    from mpmath import acos, cos, exp, floor, mp, mpf, pi, sin, sqrt
except ImportError:
    sys.exit("error: this script needs mpmath (Debian: python3-mpmath)")


def flights(zeta, omega, sigma, r, digits, count):
    """The first `count` flights from the release: (periods flown, index of
    the period the stick began in, counted from the release's, impacts), or
    None for a flight that meets no stick within 400 periods."""
    mp.dps = digits
    zeta, omega, sigma, r = mpf(zeta), mpf(omega), mpf(sigma), mpf(r)
    period = 2 * pi / omega
    det = (1 - omega**2) ** 2 + (2 * zeta * omega) ** 2
    a, b = (1 - omega**2) / det, 2 * zeta * omega / det
    wd = sqrt(1 - zeta**2)
    bisections = int(digits * 3.4) + 10
    stick_speed = mpf(10) ** (-(digits // 2))

    def forced(t):
        return a * cos(omega * t) + b * sin(omega * t)

    def forced_rate(t):
        return omega * (-a * sin(omega * t) + b * cos(omega * t))

    def free(t0, x0, v0):
        c1 = x0 - forced(t0)
        return t0, c1, (v0 - forced_rate(t0) + zeta * c1) / wd

    def gap(f, t):
        t0, c1, c2 = f
        s = t - t0
        return exp(-zeta * s) * (c1 * cos(wd * s) + c2 * sin(wd * s)) + forced(t) - sigma

    def rate(f, t):
        t0, c1, c2 = f
        s = t - t0
        c, n = cos(wd * s), sin(wd * s)
        return exp(-zeta * s) * (-zeta * (c1 * c + c2 * n) + wd * (c2 * c - c1 * n)) + forced_rate(t)

    def root(g, lo, hi):
        g_lo = g(lo)
        for _ in range(bisections):
            mid = (lo + hi) / 2
            if (g(mid) > 0) == (g_lo > 0):
                lo = mid
            else:
                hi = mid
        return hi

    def next_impact(f, t0, step, end):
        t = t0
        while t < end:
            u = t + step
            if gap(f, u) >= 0:
                return root(lambda s: gap(f, s), t, u)
            if rate(f, t) > 0 > rate(f, u):
                top = root(lambda s: rate(f, s), t, u)
                if gap(f, top) >= 0:
                    return root(lambda s: gap(f, s), t, top)
            t, step = u, min(step * 1.5, period / 64)
        return None

    # The phase of every release: cos(omega t) falls through sigma.
    phase = acos(sigma)
    release = phase / omega
    out = []
    for _ in range(count):
        f, t, step, impacts = free(release, sigma, mpf(0)), release, period / 64, 0
        end = release + 400 * period
        while True:
            hit = next_impact(f, t, step, end)
            if hit is None:
                out.append(None)
                return out
            impacts += 1
            speed, force = rate(f, hit), cos(omega * hit) - sigma
            if speed < stick_speed and force > 0:
                break
            f, t = free(hit, sigma, -r * speed), hit
            # Pressed back into the stop, the mass returns after about 2 r v / F.
            step = min(period / 64, r * speed / force / 8) if force > 0 else period / 64
        out.append(((hit - release) / period, int(floor(hit / period) - floor(release / period)), impacts))
        turns = floor((omega * hit - phase) / (2 * pi)) + 1
        release = (phase + 2 * pi * turns) / omega
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--zeta", type=float, required=True)
    ap.add_argument("--omega", type=float, required=True)
    ap.add_argument("--sigma", type=float, default=0.0)
    ap.add_argument("--r", type=float, default=0.8)
    ap.add_argument("--digits", type=int, default=40)
    ap.add_argument("--flights", type=int, default=1)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    if not all(math.isfinite(v) for v in (args.zeta, args.omega, args.sigma, args.r)):
        sys.exit("error: --zeta, --omega, --sigma and --r must be finite numbers")
    if not -1.0 < args.sigma < 1.0:
        sys.exit("error: --sigma must lie in (-1, 1): at or above 1 the force never presses the mass into its stop, at or below -1 it never lets it go")
    if not 0.0 <= args.zeta < 1.0 or args.omega <= 0.0 or not 0.0 <= args.r <= 1.0:
        sys.exit("error: --zeta must lie in [0, 1), --omega above 0 and --r in [0, 1]")
    if args.zeta == 0.0 and args.omega == 1.0:
        sys.exit("error: --omega 1 with --zeta 0 is the resonance: no bounded forced response")
    if args.digits < 20 or args.flights < 1:
        sys.exit("error: --digits must be at least 20 and --flights at least 1")
    found = flights(args.zeta, args.omega, args.sigma, args.r, args.digits, args.flights)
    if args.json:
        print(json.dumps([None if f is None else {"periods": float(f[0]), "stick_period": f[1], "impacts": f[2]} for f in found]))
        return
    for f in found:
        if f is None:
            print("no stick within 400 periods")
        else:
            print(f"stuck after {float(f[0]):.6f} periods, in period +{f[1]} from the release's ({f[2]} impacts)")


if __name__ == "__main__":
    main()
