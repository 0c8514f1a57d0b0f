"""A hand-written Z3 script for `catc diagnose examples/lifelong/budget-cut.cat` — the
reference that the diagnose row of benchmarks/startup_bench.py is compared with.  Same
question, written directly against the Z3 Python API the way a user would without catc: the
deployed composition (buy-lidar, buy-camera, buy-radio, map-site, inspect, send-report) over
8 steps, one action a step, each of them run, every constraint of the model tracked by a label, then the
solver's unsat core shrunk by deletion to an irreducible one.  It prints that core: the
initial budget against the LiDAR's price.
"""

import z3

K = 8
MODULES = ["lidar", "camera", "radio"]
PRICE = {"lidar": 20000, "camera": 150, "radio": 210}

s = z3.Solver()
budget = [z3.Real(f"budget{t}") for t in range(K + 1)]
mounted = {m: [z3.Bool(f"mounted-{m}{t}") for t in range(K + 1)] for m in MODULES}
mapped = [z3.Bool(f"mapped{t}") for t in range(K + 1)]
inspected = [z3.Bool(f"inspected{t}") for t in range(K + 1)]
reported = [z3.Bool(f"reported{t}") for t in range(K + 1)]
buy = {m: [z3.Bool(f"buy-{m}{t}") for t in range(K)] for m in MODULES}
map_site = [z3.Bool(f"map-site{t}") for t in range(K)]
inspect = [z3.Bool(f"inspect{t}") for t in range(K)]
send = [z3.Bool(f"send-report{t}") for t in range(K)]
actions = [*buy.values(), map_site, inspect, send]

labelled: dict[str, list[z3.BoolRef]] = {}


def track(label: str, *constraints: z3.BoolRef) -> None:
    labelled.setdefault(label, []).extend(constraints)


track("init budget = 500", budget[0] == 500)
track("init mounted = {}", *(z3.Not(mounted[m][0]) for m in MODULES))
track("init mapped/inspected/reported = false", z3.Not(mapped[0]), z3.Not(inspected[0]), z3.Not(reported[0]))
for t in range(K):
    s.add(z3.AtMost(*(a[t] for a in actions), 1))  # one action a step (the encoding, not a label)
    for m in MODULES:
        track(f"pre buy-{m}: budget >= {PRICE[m]}", z3.Implies(buy[m][t], budget[t] >= PRICE[m]))
        s.add(mounted[m][t + 1] == z3.Or(mounted[m][t], buy[m][t]))
    track("pre map-site: lidar mounted", z3.Implies(map_site[t], mounted["lidar"][t]))
    track("pre inspect: mapped, camera mounted", z3.Implies(inspect[t], z3.And(mapped[t], mounted["camera"][t])))
    track("pre send-report: inspected, radio mounted", z3.Implies(send[t], z3.And(inspected[t], mounted["radio"][t])))
    s.add(budget[t + 1] == budget[t] - z3.Sum([z3.If(buy[m][t], PRICE[m], 0) for m in MODULES]))
    s.add(mapped[t + 1] == z3.Or(mapped[t], map_site[t]))
    s.add(inspected[t + 1] == z3.Or(inspected[t], inspect[t]))
    s.add(reported[t + 1] == z3.Or(reported[t], send[t]))
for name, a in zip([*(f"buy-{m}" for m in MODULES), "map-site", "inspect", "send-report"], actions):
    s.add(z3.Or(a))  # the deployed composition: each of its morphisms runs
    track(f"uses {name} <= 1", z3.AtMost(*a, 1))
track("goal reported", reported[K])

flags = {}
for label, constraints in labelled.items():
    flag = flags[label] = z3.Bool(f"[{label}]")
    s.add(z3.Implies(flag, z3.And(constraints)))

if s.check(*flags.values()) == z3.sat:
    print("sat: nothing conflicts")
else:
    core = [str(f) for f in s.unsat_core()]
    for label in list(core):  # deletion: drop a label whenever the rest still conflicts
        rest = [flags[c[1:-1]] for c in core if c != label]
        if s.check(*rest) == z3.unsat:
            core.remove(label)
    print(f"unsat: {len(core)} of {len(flags)} labelled constraints conflict")
    for label in core:
        print(" ", label[1:-1])
