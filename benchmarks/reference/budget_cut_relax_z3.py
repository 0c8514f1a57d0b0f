"""A hand-written Z3 script for `catc relax examples/lifelong/budget-cut.cat` — the reference
that the relax row of benchmarks/startup_bench.py is compared with.  Same question, written
directly against the Z3 Python API the way a user would without catc: the deployed
composition (buy-lidar, buy-camera, buy-radio, map-site, inspect, send-report) over 8 steps,
one action a step, each of them run; every numeric requirement it may loosen — the initial
budget and the three prices it checks the budget against — gets a slack of its own (≥ 0,
weight 1), and one Optimize call minimises their sum.  It prints the least restoration's
cost (19,860 USD, as catc's) and the composition it makes possible; where several
restorations are least (the budget raised by all of it, or partly the radio's price check
lowered), it may give another of them than catc does.
"""

import z3

K = 8
MODULES = ["lidar", "camera", "radio"]
PRICE = {"lidar": 20000, "camera": 150, "radio": 210}

o = z3.Optimize()
budget = [z3.Real(f"budget{t}") for t in range(K + 1)]
mounted = {m: [z3.Bool(f"mounted-{m}{t}") for t in range(K + 1)] for m in MODULES}
mapped = [z3.Bool(f"mapped{t}") for t in range(K + 1)]
inspected = [z3.Bool(f"inspected{t}") for t in range(K + 1)]
reported = [z3.Bool(f"reported{t}") for t in range(K + 1)]
buy = {m: [z3.Bool(f"buy-{m}{t}") for t in range(K)] for m in MODULES}
map_site = [z3.Bool(f"map-site{t}") for t in range(K)]
inspect = [z3.Bool(f"inspect{t}") for t in range(K)]
send = [z3.Bool(f"send-report{t}") for t in range(K)]
names = [*(f"buy-{m}" for m in MODULES), "map-site", "inspect", "send-report"]
actions = [*buy.values(), map_site, inspect, send]

slack_budget = z3.Real("slack-budget")  # the initial budget raised by this much
slack_price = {m: z3.Real(f"slack-buy-{m}") for m in MODULES}  # a price's check lowered by this much
o.add(slack_budget >= 0, *(s >= 0 for s in slack_price.values()))

o.add(budget[0] == 500 + slack_budget)
o.add(*(z3.Not(mounted[m][0]) for m in MODULES), z3.Not(mapped[0]), z3.Not(inspected[0]), z3.Not(reported[0]))
for t in range(K):
    o.add(z3.AtMost(*(a[t] for a in actions), 1))
    for m in MODULES:
        o.add(z3.Implies(buy[m][t], budget[t] >= PRICE[m] - slack_price[m]))
        o.add(mounted[m][t + 1] == z3.Or(mounted[m][t], buy[m][t]))
    o.add(z3.Implies(map_site[t], mounted["lidar"][t]))
    o.add(z3.Implies(inspect[t], z3.And(mapped[t], mounted["camera"][t])))
    o.add(z3.Implies(send[t], z3.And(inspected[t], mounted["radio"][t])))
    o.add(budget[t + 1] == budget[t] - z3.Sum([z3.If(buy[m][t], PRICE[m], 0) for m in MODULES]))
    o.add(mapped[t + 1] == z3.Or(mapped[t], map_site[t]))
    o.add(inspected[t + 1] == z3.Or(inspected[t], inspect[t]))
    o.add(reported[t + 1] == z3.Or(reported[t], send[t]))
for a in actions:
    o.add(z3.Or(a), z3.AtMost(*a, 1))  # each deployed morphism runs, once
o.add(reported[K])
o.minimize(slack_budget + z3.Sum(list(slack_price.values())))

if o.check() == z3.sat:
    m = o.model()
    print("relaxed, cost", m.eval(slack_budget + z3.Sum(list(slack_price.values()))).as_fraction())
    print("  budget +", m.eval(slack_budget).as_fraction())
    for mod in MODULES:
        if m.eval(slack_price[mod]).as_fraction() != 0:
            print(f"  price check of buy-{mod} -", m.eval(slack_price[mod]).as_fraction())
    for t in range(K):
        for name, a in zip(names, actions):
            if z3.is_true(m.eval(a[t])):
                print(t + 1, name)
else:
    print("no relaxation restores the composition")
