"""Longest paths through a control-flow graph with loops: the graph half of :mod:`wake.firmware.wcet`.

A graph is ``edges``: node -> list of ``(successor, (instructions, cycles))``
(successor None: the function returns), with ``node`` costs beside it.
"""

from __future__ import annotations

__all__ = ["dag_longest", "natural_loops"]


def natural_loops(edges, entry) -> dict:
    """The natural loops of the DFS back edges from ``entry``: header -> set of the nodes of its body."""
    back, state, order = set(), {}, []

    def dfs(u):
        state[u] = 1
        for v, _ in edges[u]:
            if v is None:
                continue
            if state.get(v) == 1:
                back.add((u, v))
            elif v not in state:
                dfs(v)
        state[u] = 2
        order.append(u)

    dfs(entry)
    loops = {}
    for u, h in back:
        body, work = {h, u}, [u]
        preds = {b: [a for a in edges if any(t == b for t, _ in edges[a])] for b in edges}
        while work:
            x = work.pop()
            if x == h:
                continue
            for p in preds[x]:
                if p not in body:
                    body.add(p)
                    work.append(p)
        loops.setdefault(h, set()).update(body)
    return loops


def dag_longest(src, node, edges, *, inside, stop):
    """Longest (instructions, cycles) from src to each node, node costs included (acyclic part)."""
    order, seen = [], set()

    def visit(u):
        seen.add(u)
        for v, _ in edges.get(u, []):
            if v is None or v == stop or (inside is not None and v not in inside) or v in seen:
                continue
            visit(v)
        order.append(u)

    visit(src)
    dist = {src: node[src]}
    for u in reversed(order):
        if u not in dist:
            continue
        for v, (en, ec) in edges.get(u, []):
            if v is None or v == stop or (inside is not None and v not in inside):
                continue
            cand = (dist[u][0] + en + node[v][0], dist[u][1] + ec + node[v][1])
            old = dist.get(v)
            dist[v] = cand if old is None else (max(old[0], cand[0]), max(old[1], cand[1]))
    return dist
