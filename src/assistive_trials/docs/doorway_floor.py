#!/usr/bin/env python3
# Floor: how well could ANY cue policy pass an 0.80-0.90 m doorway, given the modelled wearer?
import numpy as np
rng = np.random.default_rng(1)
N = 200000
D2R = np.pi/180
v = rng.uniform(0.9, 1.4, N)
tau = rng.uniform(0.3, 1.2, N)
sig = rng.uniform(1, 3, N) * D2R          # rad/sqrt(m) heading random walk
men = rng.random(N) < 0.5
def tn(mu, sd, lo, hi, n):
    x = rng.normal(mu, sd, n)
    bad = (x < lo) | (x > hi)
    while bad.any():
        x[bad] = rng.normal(mu, sd, bad.sum()); bad = (x < lo) | (x > hi)
    return x
r = np.where(men, (tn(465, 28, 420, 510, N) + 10) / 2000, (tn(395, 24, 355, 435, N) + 10) / 2000)
w = rng.uniform(0.80, 0.90, N)
margin = w / 2 - r
def rw_lat(D):  # lateral error from the heading random walk over D metres (exact sample)
    return sig * np.sqrt(D**3 / 3) * rng.standard_normal(N)
def report(name, lat, sel=None):
    hit = np.abs(lat) > margin
    s = np.ones(N, bool) if sel is None else sel
    print(f"{name}: P(touch a jamb) per doorway = {hit[s].mean()*100:.1f} %  (lateral sd {lat[s].std()*100:.1f} cm, margin mean {margin[s].mean()*100:.1f} cm, min {margin[s].min()*100:.1f})")
slow = tau >= np.quantile(tau, 0.9)
# A: walking through, oracle veer controller that knows everything up to its decision; the
# last decision acts after reaction + first pulse (0.15 s) + the veer's own execution (15 deg at
# 60 deg/s = 0.25 s): the random walk over that distance and one 15-deg veer's spread
# (lognormal 0.15 per veer: 2.25 deg sd) over the rest are unseen.
D = v * (tau + 0.15 + 0.25)
veer_noise = 15 * D2R * (np.exp(rng.normal(0, 0.15, N)) - 1)
latA = rw_lat(D) + veer_noise * D / 2
report("A walking through, oracle, all", latA); report("A slowest decile", latA, slow)
# A': the same with no final veer needed (already aligned): random walk only
report("A' random walk only over the reaction distance", rw_lat(D))
# B: stop-and-align 0.9 m before the doorway, turned (exactly, as the model turns on the spot)
# until the HEAD faces the middle: the body is off by the head's scan (8 deg sinusoid, 7 s)
D0 = 0.9
scan = 8 * D2R * np.sin(rng.uniform(0, 2*np.pi, N))
latB = D0 * np.sin(scan) + rw_lat(D0)
report("B stop-and-align at 0.9 m (head scan 8 deg)", latB)
report("B' the same if the body's yaw were known (no scan error)", rw_lat(D0))
# C: 3 doorways a walk: P(no touch)
pA = (np.abs(latA) > margin).mean(); pB = (np.abs(latB) > margin).mean()
print(f"P(a walk through 3 doorways without a touch): A {(1-pA)**3*100:.0f} %, B {(1-pB)**3*100:.0f} %")
# PPWS floor: a straight walk of L m the guide walks in L/v; the wearer adds its reaction to the
# first 'go' and the acceleration (1.2 m/s^2: v/2.4 s lost); each stop-and-turn adds about
# stop (v/4.8) + reaction + the turn (0.25 s tell-apart + angle/90deg/s) + reaction + v/2.4.
for L in (10, 15, 20):
    t0 = L / v
    base = t0 + tau + v / 2.4
    print(f"PPWS floor, {L} m straight: mean {np.mean(t0/base)*100:.0f} %, slowest decile {np.mean((t0/base)[slow])*100:.0f} %;"
          f" with one stop-and-turn (30 deg): mean {np.mean(t0/(base + v/4.8 + 2*tau + 0.25 + 30/90 + v/2.4))*100:.0f} %;"
          f" with 3: {np.mean(t0/(base + 3*(v/4.8 + 2*tau + 0.25 + 30/90 + v/2.4)))*100:.0f} %")
