"""The networkx side of `cargo bench --bench stn_vs_networkx`.

Reads the distance graphs the Rust side wrote (one file per network: a first line
`points origin`, then one `u v w` line per edge, meaning t(v) - t(u) <= w) and times, for each,
what the paper does with networkx: a consistency check (`negative_edge_cycle`), then the
earliest-start schedule (Bellman-Ford from the origin on the reversed graph: the earliest time
of a point is minus its shortest distance to the origin). It also times the cheapest way
networkx offers to get both at once (the same Bellman-Ford alone, which raises on a negative
cycle reachable from the origin, and every point reaches it).

Graph construction is not timed. Prints one JSON object per network on stdout.
"""

import json
import sys
import time

import networkx as nx


def load(path):
    with open(path) as f:
        points, origin = map(int, f.readline().split())
        graph = nx.DiGraph()
        graph.add_nodes_from(range(points))
        for line in f:
            u, v, w = line.split()
            graph.add_edge(int(u), int(v), weight=int(w))
    return graph, origin


def best_of(runs, job):
    best, result = float("inf"), None
    for _ in range(runs):
        started = time.perf_counter()
        result = job()
        best = min(best, time.perf_counter() - started)
    return best, result


def earliest(graph, origin):
    reversed_graph = graph.reverse(copy=False)
    try:
        distances = nx.single_source_bellman_ford_path_length(reversed_graph, origin, weight="weight")
    except nx.NetworkXUnbounded:
        return None
    return max(-d for d in distances.values())


def paper_way(graph, origin):
    if nx.negative_edge_cycle(graph, weight="weight"):
        return None
    return earliest(graph, origin)


def main():
    runs = int(sys.argv[1])
    for path in sys.argv[2:]:
        graph, origin = load(path)
        # One run of the paper's way where it takes tens of seconds.
        n = graph.number_of_nodes()
        paper, makespan = best_of(runs if n <= 5001 else 1, lambda: paper_way(graph, origin))
        single, makespan_single = best_of(runs, lambda: earliest(graph, origin))
        assert makespan == makespan_single
        print(json.dumps({"path": path, "paper_way": paper, "bellman_ford": single, "makespan": makespan}), flush=True)


if __name__ == "__main__":
    main()
