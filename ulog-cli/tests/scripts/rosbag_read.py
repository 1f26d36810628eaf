"""Opens a ROS 2 bag folder with `rosbags` and prints, per connection, its message
type, the count its metadata gives, and the messages read and deserialized with the
types defined by the bag's own message definitions.

Usage: rosbag_read.py BAG_DIR  (prints one JSON object)
"""

import json
import sys

from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_types_from_msg, get_typestore


def main():
    out = {}
    with Reader(sys.argv[1]) as reader:
        store = get_typestore(Stores.EMPTY)
        types = {}
        for conn in reader.connections:
            types.update(get_types_from_msg(conn.msgdef.data, conn.msgtype))
        store.register(types)
        for conn in reader.connections:
            out[conn.topic] = {"type": conn.msgtype, "count": conn.msgcount, "read": 0}
        for conn, _timestamp, raw in reader.messages():
            store.deserialize_cdr(raw, conn.msgtype)
            out[conn.topic]["read"] += 1
        total = reader.message_count
    json.dump({"topics": out, "message_count": total}, sys.stdout)


main()
