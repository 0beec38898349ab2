#!/usr/bin/env python3
"""Pinocchio peer for virtual-physics: reference fixtures and ABA timings.

The models are NOT defined here: they are the JSON descriptions that `vphys peers models`
writes (from `virtual_physics::model::builders`), read by this script, so both sides use the
same numbers. Requires Pinocchio (`pip install pin`).

    python3 pinocchio_fixtures.py fixtures MODEL.json... --out DIR [--states 3] [--seed 1]
        For each model, random states (q, v, tau) in virtual-physics coordinates, Pinocchio's
        aba -> qdd, written to DIR/<name>.json together with the model description.
    python3 pinocchio_fixtures.py bench MODEL.json... [--batch 256] [--repeats 30]
        Prints {"<name>": microseconds per aba call, ...}: Pinocchio's aba through its C++
        batch loop (abaInParallel, one thread), so Python overhead does not count.

Coordinates (virtual-physics -> Pinocchio):
  revolute / prismatic: identical (RX/RY/RZ/PX/PY/PZ for aligned axes, *Unaligned otherwise).
  ball: q = exponential coordinates r (3) -> quaternion [x, y, z, w] of exp(r);
        v, a, tau identical (angular velocity / acceleration / moment in the child frame).
  free: q = [r (3), p (3)] -> [p, quaternion of exp(r)];
        v = [w, v] (angular first) -> Pinocchio [v, w] (linear first); a and tau likewise.
"""
import argparse
import json
import sys
import time

try:
    import numpy as np
    import pinocchio as pin
except ImportError as e:  # pragma: no cover
    sys.stderr.write(f"Pinocchio is not installed ({e}): pip install pin\n")
    sys.exit(3)

AXES = {(1.0, 0.0, 0.0): "X", (0.0, 1.0, 0.0): "Y", (0.0, 0.0, 1.0): "Z"}


def joint_model(j):
    kind = j["type"]
    if kind in ("revolute", "prismatic"):
        axis = np.array(j["axis"], dtype=float)
        axis /= np.linalg.norm(axis)
        name = AXES.get(tuple(float(x) for x in axis))
        prefix = "R" if kind == "revolute" else "P"
        if name is not None:
            return getattr(pin, f"JointModel{prefix}{name}")()
        if kind == "revolute":
            return pin.JointModelRevoluteUnaligned(axis)
        return pin.JointModelPrismaticUnaligned(axis)
    if kind == "ball":
        return pin.JointModelSpherical()
    if kind == "free":
        return pin.JointModelFreeFlyer()
    raise ValueError(f"joint type '{kind}' is not used by the peer models")


def build(desc):
    model = pin.Model()
    model.gravity.linear = np.array(desc["gravity"], dtype=float)
    model.gravity.angular = np.zeros(3)
    ids = []
    for b in desc["bodies"]:
        parent = 0 if b["parent"] is None else ids[b["parent"]]
        placement = pin.SE3(
            np.array(b["placement"]["rotation"], dtype=float),
            np.array(b["placement"]["translation"], dtype=float),
        )
        jid = model.addJoint(parent, joint_model(b["joint"]), placement, b["name"])
        i = b["inertia"]
        c = i["inertia_com"]
        ic = np.array([[c[0], c[3], c[4]], [c[3], c[1], c[5]], [c[4], c[5], c[2]]])
        model.appendBodyToJoint(
            jid, pin.Inertia(i["mass"], np.array(i["com"], dtype=float), ic), pin.SE3.Identity()
        )
        ids.append(jid)
    return model


def dims(j):
    return {"revolute": (1, 1), "prismatic": (1, 1), "ball": (3, 3), "free": (6, 6)}[j["type"]]


def random_state(desc, rng):
    """A random (q, v, tau) in virtual-physics coordinates."""
    q, v, tau = [], [], []
    for b in desc["bodies"]:
        kind = b["joint"]["type"]
        nq, nv = dims(b["joint"])
        if kind == "revolute":
            q.append(rng.uniform(-np.pi, np.pi))
        elif kind == "prismatic":
            q.append(rng.uniform(-0.2, 0.2))
        else:
            axis = rng.normal(size=3)
            r = axis / np.linalg.norm(axis) * rng.uniform(0.0, 3.0)
            q.extend(r.tolist())
            if kind == "free":
                q.extend(rng.uniform(-1.0, 1.0, size=3).tolist())
        v.extend(rng.normal(size=nv).tolist())
        tau.extend((5.0 * rng.normal(size=nv)).tolist())
    return np.array(q), np.array(v), np.array(tau)


def to_pin(desc, model, q, v, tau):
    """virtual-physics (q, v, tau) -> Pinocchio's."""
    pq, pv, pt = np.zeros(model.nq), np.zeros(model.nv), np.zeros(model.nv)
    oq = ov = 0
    for k, b in enumerate(desc["bodies"]):
        jm = model.joints[k + 1]
        iq, iv = jm.idx_q, jm.idx_v
        kind = b["joint"]["type"]
        nq, nv = dims(b["joint"])
        if kind in ("revolute", "prismatic"):
            pq[iq] = q[oq]
            pv[iv], pt[iv] = v[ov], tau[ov]
        elif kind == "ball":
            pq[iq : iq + 4] = pin.Quaternion(pin.exp3(q[oq : oq + 3])).coeffs()
            pv[iv : iv + 3], pt[iv : iv + 3] = v[ov : ov + 3], tau[ov : ov + 3]
        else:  # free
            pq[iq : iq + 3] = q[oq + 3 : oq + 6]
            pq[iq + 3 : iq + 7] = pin.Quaternion(pin.exp3(q[oq : oq + 3])).coeffs()
            pv[iv : iv + 3], pv[iv + 3 : iv + 6] = v[ov + 3 : ov + 6], v[ov : ov + 3]
            pt[iv : iv + 3], pt[iv + 3 : iv + 6] = tau[ov + 3 : ov + 6], tau[ov : ov + 3]
        oq += nq
        ov += nv
    return pq, pv, pt


def from_pin_accel(desc, model, a):
    """Pinocchio's joint accelerations -> virtual-physics order."""
    out = []
    for k, b in enumerate(desc["bodies"]):
        iv = model.joints[k + 1].idx_v
        nv = dims(b["joint"])[1]
        x = a[iv : iv + nv]
        if b["joint"]["type"] == "free":
            x = np.concatenate([x[3:6], x[0:3]])
        out.extend(x.tolist())
    return out


def cmd_fixtures(args):
    for path in args.models:
        with open(path) as f:
            desc = json.load(f)
        model = build(desc)
        data = model.createData()
        rng = np.random.default_rng(args.seed)
        states = []
        for _ in range(args.states):
            q, v, tau = random_state(desc, rng)
            pq, pv, pt = to_pin(desc, model, q, v, tau)
            a = pin.aba(model, data, pq, pv, pt)
            states.append(
                {
                    "q": q.tolist(),
                    "qd": v.tolist(),
                    "tau": tau.tolist(),
                    "qdd": from_pin_accel(desc, model, np.array(a)),
                }
            )
        out = {
            "generator": f"pinocchio {pin.__version__} aba, peers/pinocchio_fixtures.py seed {args.seed}",
            "model": desc,
            "states": states,
        }
        name = f"{args.out}/{desc['name']}.json"
        with open(name, "w") as f:
            json.dump(out, f, separators=(",", ":"))
            f.write("\n")
        print(f"wrote {name}: {len(states)} states, nv = {model.nv}")


def cmd_bench(args):
    results = {}
    for path in args.models:
        with open(path) as f:
            desc = json.load(f)
        model = build(desc)
        rng = np.random.default_rng(7)
        cols = [to_pin(desc, model, *random_state(desc, rng)) for _ in range(args.batch)]
        q = np.asfortranarray(np.stack([c[0] for c in cols], axis=1))
        v = np.asfortranarray(np.stack([c[1] for c in cols], axis=1))
        tau = np.asfortranarray(np.stack([c[2] for c in cols], axis=1))
        a = np.asfortranarray(np.zeros((model.nv, args.batch)))
        pool = pin.ModelPool(model, 1)
        pin.abaInParallel(1, pool, q, v, tau, a)
        best = float("inf")
        for _ in range(args.repeats):
            t = time.perf_counter()
            pin.abaInParallel(1, pool, q, v, tau, a)
            best = min(best, (time.perf_counter() - t) / args.batch)
        results[desc["name"]] = best * 1e6
    json.dump({"pinocchio": pin.__version__, "us": results}, sys.stdout)
    sys.stdout.write("\n")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="cmd", required=True)
    f = sub.add_parser("fixtures")
    f.add_argument("models", nargs="+")
    f.add_argument("--out", required=True)
    f.add_argument("--states", type=int, default=3)
    f.add_argument("--seed", type=int, default=1)
    b = sub.add_parser("bench")
    b.add_argument("models", nargs="+")
    b.add_argument("--batch", type=int, default=256)
    b.add_argument("--repeats", type=int, default=30)
    args = p.parse_args()
    {"fixtures": cmd_fixtures, "bench": cmd_bench}[args.cmd](args)


if __name__ == "__main__":
    main()
