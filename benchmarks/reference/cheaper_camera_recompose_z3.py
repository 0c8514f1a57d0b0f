"""A hand-written Z3 script for `catc recompose examples/lifelong/cheaper-camera.cat` — the
reference that the recompose row of benchmarks/startup_bench.py is compared with.  Same
question, written directly against the Z3 Python API the way a user would without catc: the
inspection domain's eight components (four purchases, mapping, two inspections, the report)
over 8 steps, one action a step, each component at most once; the budget is back at
20,360 USD.  Against the deployed composition (buy-lidar, buy-camera, buy-radio, map-site,
inspect, send-report), one Optimize call minimises the churn — the components added plus
the components removed — and then, lexicographically, maximises the budget left (stability
first, as `catc recompose` answers by default).  It prints churn 0 and 0 USD left (as catc),
the components added and removed (none) and the composition.  With ``--objective-first``
the two objectives swap (`catc recompose --priority objective`): 100 USD left by the lite
camera and its inspection software, churn 4.
"""

import sys

import z3

K = 8
BUDGET = 20360
MODULES = ["lidar", "camera", "camera-lite", "radio"]
PRICE = {"lidar": 20000, "camera": 150, "camera-lite": 50, "radio": 210}
DEPLOYED = {"buy-lidar", "buy-camera", "buy-radio", "map-site", "inspect", "send-report"}

o = z3.Optimize()
budget = [z3.Real(f"budget{t}") for t in range(K + 1)]
mounted = {m: [z3.Bool(f"mounted-{m}{t}") for t in range(K + 1)] for m in MODULES}
mapped = [z3.Bool(f"mapped{t}") for t in range(K + 1)]
inspected = [z3.Bool(f"inspected{t}") for t in range(K + 1)]
reported = [z3.Bool(f"reported{t}") for t in range(K + 1)]
buy = {m: [z3.Bool(f"buy-{m}{t}") for t in range(K)] for m in MODULES}
map_site = [z3.Bool(f"map-site{t}") for t in range(K)]
inspect = [z3.Bool(f"inspect{t}") for t in range(K)]
inspect_lite = [z3.Bool(f"inspect-lite{t}") for t in range(K)]
send = [z3.Bool(f"send-report{t}") for t in range(K)]
actions = {
    **{f"buy-{m}": buy[m] for m in MODULES},
    "map-site": map_site,
    "inspect": inspect,
    "inspect-lite": inspect_lite,
    "send-report": send,
}

o.add(budget[0] == BUDGET)
o.add(*(z3.Not(mounted[m][0]) for m in MODULES), z3.Not(mapped[0]), z3.Not(inspected[0]), z3.Not(reported[0]))
for t in range(K):
    o.add(z3.AtMost(*(a[t] for a in actions.values()), 1))
    for m in MODULES:
        o.add(z3.Implies(buy[m][t], budget[t] >= PRICE[m]))
        o.add(mounted[m][t + 1] == z3.Or(mounted[m][t], buy[m][t]))
    o.add(z3.Implies(map_site[t], mounted["lidar"][t]))
    o.add(z3.Implies(inspect[t], z3.And(mapped[t], mounted["camera"][t])))
    o.add(z3.Implies(inspect_lite[t], z3.And(mapped[t], mounted["camera-lite"][t])))
    o.add(z3.Implies(send[t], z3.And(inspected[t], mounted["radio"][t])))
    o.add(budget[t + 1] == budget[t] - z3.Sum([z3.If(buy[m][t], PRICE[m], 0) for m in MODULES]))
    o.add(mapped[t + 1] == z3.Or(mapped[t], map_site[t]))
    o.add(inspected[t + 1] == z3.Or(inspected[t], inspect[t], inspect_lite[t]))
    o.add(reported[t + 1] == z3.Or(reported[t], send[t]))
for a in actions.values():
    o.add(z3.AtMost(*a, 1))  # each component at most once (:uses 1)
o.add(reported[K])
used = {name: z3.Or(a) for name, a in actions.items()}
churn = z3.Sum([z3.If(u if name not in DEPLOYED else z3.Not(u), 1, 0) for name, u in used.items()])
if "--objective-first" in sys.argv:
    o.maximize(budget[K])
    o.minimize(churn)
else:
    o.minimize(churn)  # stability first ...
    o.maximize(budget[K])  # ... then the mission's objective (Z3's default priority: lexicographic)

if o.check() == z3.sat:
    m = o.model()
    print("churn", m.eval(churn), "budget left", m.eval(budget[K]).as_fraction())
    print("added", sorted(n for n, u in used.items() if n not in DEPLOYED and z3.is_true(m.eval(u))))
    print("removed", sorted(n for n, u in used.items() if n in DEPLOYED and not z3.is_true(m.eval(u))))
    for t in range(K):
        for name, a in actions.items():
            if z3.is_true(m.eval(a[t])):
                print(t + 1, name)
else:
    print("no composition reaches the goal")
