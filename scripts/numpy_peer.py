#!/usr/bin/env python3
"""A plain NumPy peer of the 2D swarm simulation, written from the paper (sections 2-3), to
compare the speed of our engine (swarm-sim) with a straightforward vectorised implementation.

What it runs: the sharp-border scenario (X = 0 for x < 0, X = 5 for x >= 0, noise xi uniform in
(-0.5, 0.5), fresh at every activation), 61 agents on the triangular lattice of spacing 0.75 R
(the nodes nearest the centre: a hexagon filling a 6 R disk), perception range R = 1, the swarm
centred at (-2.5, 0). One negotiation period per run, as our engine does it with
`Params::simulation_2d()`: one gathering cycle and one deciding cycle of t_p^max = 1000 s each
(both start at second 0 for every agent), one initiation per agent and cycle at a uniform
integer second in (start, start + 1000], relay delay 1 s, refractory time 10 s. Gathering
(Alg. 1): a message carries the readings along its path (up to 32; the oldest dropped); an
inactive agent that hears it appends its own reading, scores the message by the population
variance and stores that score under the exact bearing it heard it from, and relays it one
second later. Evaluation (Alg. 2): the preferred bearing is the one with the largest average
variance (strictly largest and > 0, otherwise none). Deciding (Alg. 3): waves carry opinions;
an activated agent turns its preferred bearing 10 % of the shorter arc toward the received
one (adopts it if it has none). At the period's end the swarm moves 0.33 R along the circular
mean of the decisions. Senders are served by increasing index; an agent activated by a
message ignores the others of that second; messages of the other phase are ignored. Time
jumps from one due second to the next (as the engine's calendar does): idle seconds cost
nothing here either.

It is a peer, not a copy: its random draws differ from the engine's, so the runs are
statistically, not bit for bit, the same (it prints the mean consensus and step direction as
a sanity check).

Measured (2 shared cores, commit 1ff4c2a of branch `speed`, one thread each, 100 runs):
NumPy 4.11 s event to event (41 ms per run), 5.63 s with --every-second (56 ms per run);
the engine 0.063 s per 100 runs in the real release profile (fat LTO; 1000 runs: 0.63 s user),
0.072 s in the fast profile (1000 runs: 0.72 s user), 0.13 s before the branch: about 65 times
faster than this peer (90 times against --every-second), not the 300 times aimed at (the
engine's sweep does not pool V_k, which only the observer reads; this peer does). This peer
is vectorised over the agents (one NumPy step per busy second, not a Python loop per agent),
which is what a plain NumPy port looks like.

Measured again on 2026-11-28 (night, main after issue 38's engine work: relays and rests queued
apart from the timers, short ways for a lone rest and a first relay, messages scored over the
slice; the same runs bit for bit): this peer 38.5 and 41.0 ms per run (two runs of 100); the
engine 0.76 s user for 2000 runs in the real release profile (the sweep command below with
`--runs 2000`, process start and CSV/SVG included), 0.38 ms per run: about 100 times faster
(before that work 0.63 ms, 61 times).

Measured again on 2026-11-29 (main after the second round: messages read where their senders
keep them, rests left to the agent's next call, one reading drawn per activation or initiation
(a new noise stream, so not the same runs as before), a heard message handled in one pass):
this peer 38.5 ms per run (100 runs); the engine 0.57 s user for the same 2000 runs, 0.29 ms
per run: about 135 times faster, not the 300 times aimed at. docs/reproduction.md's Speed line
times the same work (the observer's V_k pooled, as this peer does) in the run that writes the
page.

Measured again on 2026-11-29 (later; main with the lean engine, `swarm_sim::lean`: the plain
runs' three-phase rules written out over plain per-agent records, the same runs bit for bit):
this peer 38.6 ms per run (100 runs); the engine 0.38 s user for the same 2000 runs (best of
5; 0.38-0.40 s), 0.19 ms per run: about 200 times faster, still not the 300 times aimed at
(the page's Speed line, the observer's V_k pooled: 0.21 ms, 190 times).

Measured again on 2026-11-29 (session 3; messages keep their sum, links and keys side by side,
relays in a ring: 10 % fewer instructions, the same runs bit for bit): the engine 0.37 s for
the same 2000 runs (best of 5; 0.37-0.38 s; the build before, 0.38-0.39 s, interleaved),
0.185 ms per run: about 210 times faster (the page's Speed line: 0.20 ms, 191 times). The time
fell far less than the instruction count (callgrind, 200 runs: 390.9 M -> 352.8 M): what is
left is bound by the latency of serial chains (a message's variance is a sum in order, the
noise draw, the pooled moments' divisions), which bit-for-bit runs may not reorder.

Setup (numpy was not installed on the machine; installed from PyPI):

    pip install numpy          # numpy 2.4.6 with Python 3.11.7

Measure (single thread each; 100 runs of one period):

    OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python3 scripts/numpy_peer.py --runs 100
    # our engine on the same work: a copy of the sharp scenario with periods = 1, swept at
    # x = -2.5 only, 100 runs (1000 for a steadier time), one thread; `time` gives the whole
    # command, process start and CSV/SVG included:
    sed 's/^periods = 50 .*/periods = 1/' swarm-sim/scenarios/sharp.toml > /tmp/sharp1.toml
    time RAYON_NUM_THREADS=1 target/release/cimax swarm sweep --scenario /tmp/sharp1.toml \\
        --threads 1 --from -2.5 --to -2.5 --step 1 --runs 100 --quiet --out-dir /tmp/peer
"""

import argparse
import time

import numpy as np

N_MAX = 32  # readings per message
CYCLE = 1000  # t_p^max, seconds
RELAY = 1
REFRACTORY = 10
DIFFUSION = 0.1
STEP = 0.33
NOISE = 1.0
SPACING = 0.75
AGENTS = 61

INACTIVE, ACTIVE, REFRACT = 0, 1, 2


def lattice(n, spacing):
    """The n nodes of a triangular lattice nearest the origin (ties by angle)."""
    k = int(np.ceil(np.sqrt(n))) + 2
    pts = []
    for j in range(-k, k + 1):
        for i in range(-k, k + 1):
            pts.append((spacing * (i + 0.5 * j), spacing * j * np.sqrt(3) / 2))
    pts = np.array(pts)
    d = np.round(np.hypot(pts[:, 0], pts[:, 1]), 9)
    a = np.mod(np.arctan2(pts[:, 1], pts[:, 0]), 2 * np.pi)
    order = np.lexsort((a, d))
    return pts[order[:n]]


def field(x):
    """The sharp border: X = 0 left of x = 0, 5 right of it."""
    return np.where(x < 0.0, 0.0, 5.0)


def wrap_signed(a):
    """Angle into (-pi, pi]."""
    a = np.mod(a, 2 * np.pi)
    return np.where(a > np.pi, a - 2 * np.pi, a)


def run_period(offsets, adj, bearing, centre, rng, every_second=False):
    """One negotiation period (gathering cycle, then deciding cycle) at `centre`. Returns the
    direction moved (or None), the consensus and the mean diversity V_k. With `every_second`,
    time advances one second at a time as in the paper's pseudo-code (same dynamics, the idle
    seconds are visited too)."""
    n = len(offsets)
    means = field(offsets[:, 0] + centre[0])
    ar = np.arange(n)
    state = np.full(n, INACTIVE)
    relay_at = np.full(n, -1)
    rest_at = np.full(n, -1)
    # Gathering storage: per receiver and sender, summed variance and count; pooled readings.
    wsum = np.zeros((n, n))
    wcnt = np.zeros((n, n))
    pool_n = np.zeros(n)
    pool_s = np.zeros(n)
    pool_ss = np.zeros(n)
    buf = np.zeros((n, N_MAX))  # each agent's message to relay / just sent
    blen = np.zeros(n, dtype=np.int64)
    opinion = np.full(n, np.nan)  # preferred bearing (nan: none)
    out_op = np.full(n, np.nan)
    diversity = np.zeros(n)
    for phase in (0, 1):  # 0 gathering, 1 deciding
        start = phase * CYCLE
        end = start + CYCLE
        init_at = start + rng.integers(1, CYCLE + 1, size=n)
        pending = np.zeros(n, dtype=bool)  # an agent's relay is due (none at a cycle start)
        t = start
        while True:
            # Next due second: an initiation, a relay, a refractory end or the cycle's end.
            t_next = end
            fut = init_at[init_at > t]
            if fut.size:
                t_next = min(t_next, fut.min())
            if (state == ACTIVE).any():
                t_next = min(t_next, relay_at[state == ACTIVE].min())
            if (state == REFRACT).any():
                t_next = min(t_next, rest_at[state == REFRACT].min())
            t = t + 1 if every_second else t_next
            if t > end:
                break
            # 1. Timeouts, in the engine's tie order: refractory end, relay, initiation.
            state[(state == REFRACT) & (rest_at == t)] = INACTIVE
            relays = (state == ACTIVE) & (relay_at == t)
            sending = relays & pending
            state[relays] = REFRACT
            rest_at[relays] = t + REFRACTORY
            inits = (init_at == t) & (state == INACTIVE)
            if inits.any():
                ids = ar[inits]
                if phase == 0:
                    own = means[ids] + NOISE * (rng.random(len(ids)) - 0.5)
                    buf[ids, 0] = own
                    blen[ids] = 1
                else:
                    out_op[ids] = opinion[ids]
                state[ids] = REFRACT
                rest_at[ids] = t + REFRACTORY
                sending |= inits
            if phase == 1:
                out_op[relays & pending] = opinion[relays & pending]
            pending &= ~relays
            init_at[init_at == t] = -1
            if t == end:
                # Messages of the ending phase reach agents already in the next one: ignored.
                break
            # 2. Deliveries: each inactive neighbour takes the first sender's message.
            if not sending.any():
                continue
            senders = ar[sending]
            hear = adj[senders] & (state == INACTIVE)[None, :]
            got = hear.any(axis=0)
            if not got.any():
                continue
            rcv = ar[got]
            src = senders[hear[:, got].argmax(axis=0)]
            m = len(rcv)
            if phase == 0:
                own = means[rcv] + NOISE * (rng.random(m) - 0.5)
                ln = blen[src]
                msg = buf[src].copy()
                full = ln == N_MAX
                if full.any():
                    msg[full] = np.roll(msg[full], -1, axis=1)
                    ln = np.where(full, N_MAX - 1, ln)
                # Score: the variance of the received readings and the own one.
                vals = np.concatenate([buf[src], own[:, None]], axis=1)
                k = blen[src] + 1
                mask = np.arange(N_MAX + 1)[None, :] < blen[src][:, None]
                mask[:, N_MAX] = True
                s = (vals * mask).sum(axis=1)
                mu = s / k
                v = (((vals - mu[:, None]) ** 2) * mask).sum(axis=1) / k
                wsum[rcv, src] += v
                wcnt[rcv, src] += 1
                pool_n[rcv] += k
                pool_s[rcv] += s
                pool_ss[rcv] += ((vals**2) * mask).sum(axis=1)
                msg[ar[:m], ln] = own
                buf[rcv] = msg
                blen[rcv] = ln + 1
            else:
                o = out_op[src]
                mine = opinion[rcv]
                has = ~np.isnan(o)
                adopt = has & np.isnan(mine)
                turn = has & ~np.isnan(mine)
                d = wrap_signed(o - mine)
                new = np.where(turn, np.mod(mine + DIFFUSION * d, 2 * np.pi), mine)
                new = np.where(adopt, np.mod(o, 2 * np.pi), new)
                opinion[rcv] = new
            state[rcv] = ACTIVE
            relay_at[rcv] = t + RELAY
            pending[rcv] = True
        if phase == 0:
            # Evaluation: the strictly heaviest direction, if its average is > 0.
            avg = np.where(wcnt > 0, wsum / np.maximum(wcnt, 1), -np.inf)
            best = avg.max(axis=1)
            tied = (avg == best[:, None]).sum(axis=1) > 1
            ok = (best > 0) & ~tied & np.isfinite(best)
            opinion = np.where(ok, bearing[ar, avg.argmax(axis=1)], np.nan)
            nn = np.maximum(pool_n, 1)
            diversity = np.where(pool_n >= 2, pool_ss / nn - (pool_s / nn) ** 2, 0.0)
    dec = opinion[~np.isnan(opinion)]
    if len(dec) == 0:
        return None, 0.0, diversity.mean()
    c, s = np.cos(dec).sum(), np.sin(dec).sum()
    r = np.hypot(c, s)
    if r == 0:
        return None, 0.0, diversity.mean()
    return np.arctan2(s, c), r / len(dec), diversity.mean()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--runs", type=int, default=100)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--x", type=float, default=-2.5)
    ap.add_argument(
        "--every-second",
        action="store_true",
        help="step every second (the paper's timer loop) instead of jumping to the next event",
    )
    a = ap.parse_args()
    offsets = lattice(AGENTS, SPACING)
    diff = offsets[None, :, :] - offsets[:, None, :]  # [r, s] = s - r
    dist = np.hypot(diff[..., 0], diff[..., 1])
    adj = (dist <= 1.0) & (dist > 0)
    # The bearing at which receiver r hears sender s: atan2(sender - receiver).
    bearing = np.mod(np.arctan2(diff[..., 1], diff[..., 0]), 2 * np.pi)
    rng = np.random.default_rng(a.seed)
    t0 = time.perf_counter()
    dirs, cons, divs = [], [], []
    for _ in range(a.runs):
        d, c, v = run_period(offsets, adj, bearing, np.array([a.x, 0.0]), rng, a.every_second)
        dirs.append(np.nan if d is None else d)
        cons.append(c)
        divs.append(v)
    wall = time.perf_counter() - t0
    dirs = np.array(dirs)
    mode = "every second" if a.every_second else "event to event"
    print(
        f"numpy peer ({mode}): {a.runs} runs of one period (2000 s), {AGENTS} agents, "
        f"mean degree {adj.sum() / AGENTS:.2f}"
    )
    print(
        f"  mean consensus {np.mean(cons):.3f}, mean cos(direction) "
        f"{np.nanmean(np.cos(dirs)):.3f} (toward the border: > 0), mean V_k {np.mean(divs):.3f}"
    )
    print(f"wall {wall:.3f} s ({wall / a.runs * 1000:.1f} ms per run)")


if __name__ == "__main__":
    main()
