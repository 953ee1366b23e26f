"""Loads a kbc BehaviorTree.CPP v4 XML file in BehaviorTree.CPP (through behaviortreepy) and
ticks it to the end; prints the status and the action nodes in the order they were ticked.

The bindings register Python actions without ports, so the leaves' attributes (the ports kbc
declares in TreeNodesModel) are dropped before loading: this checks the tree's structure and
node types, which BT.CPP parses and runs itself."""

import re
import sys

import behaviortreepy as bt

xml = open(sys.argv[1]).read()
ids = sorted(set(re.findall(r'<Action ID="([^"]+)"', xml)))
body = xml.split("<TreeNodesModel>")[0] + "</root>\n"
body = re.sub(r"<(\w+)( [^>]*)?/>", lambda m: "<%s/>" % m.group(1), body)
factory = bt.BehaviorTreeFactory()
ticked = []
for node_id in ids:
    factory.register_simple_action(node_id, lambda node, n=node_id: (ticked.append(n), bt.NodeStatus.SUCCESS)[1])
tree = factory.create_tree_from_text(body)
print(tree.tick_while_running())
print(" ".join(ticked))
