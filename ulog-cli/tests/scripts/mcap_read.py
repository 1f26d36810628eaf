"""Reads an MCAP file with Foxglove's readers (mcap, mcap-ros2-support) and prints,
per channel, what the Rust test compares with its own reader: the schema, the message
count, the first and last log time, and a SHA-256 over one line per message in file
order: the log time, then every value of the decoded message, depth first in field
order (integers in decimal, booleans as 0/1, floats as the bits of their float64, NaN
as `nan`, JSON's null as `null`, strings as they are). CDR messages are decoded with
the `ros2msg` schemas; JSON messages are parsed and each is validated against its
channel's JSON Schema (`jsonschema`, the reference validator: some 12,000 messages a
second, so that the first N messages of each channel are validated when N is given).

Usage: mcap_read.py FILE.mcap [N]  (prints one JSON object)
"""

import hashlib
import json
import math
import struct
import sys

import jsonschema
from mcap.reader import NonSeekingReader, make_reader
from mcap_ros2.decoder import DecoderFactory

EMPTY_MEMBER = "structure_needs_at_least_one_member"


def flatten(value, out):
    if value is None:
        out.append("null")
    elif isinstance(value, bool):
        out.append("1" if value else "0")
    elif isinstance(value, int):
        out.append(str(value))
    elif isinstance(value, float):
        if math.isnan(value):
            out.append("nan")
        else:
            out.append(str(struct.unpack("<Q", struct.pack("<d", value))[0]))
    elif isinstance(value, (bytes, bytearray)):
        out.extend(str(b) for b in value)
    elif isinstance(value, (list, tuple)):
        for v in value:
            flatten(v, out)
    elif isinstance(value, str):
        out.append(value)
    elif isinstance(value, dict):
        for v in value.values():
            flatten(v, out)
    else:
        for name in value.__slots__:
            if name != EMPTY_MEMBER:
                flatten(getattr(value, name), out)


def main():
    channels = {}
    cdr = DecoderFactory()
    decoders = {}
    validators = {}
    validated = {}
    limit = int(sys.argv[2]) if len(sys.argv) > 2 else None
    with open(sys.argv[1], "rb") as f:
        # CRCs of every chunk and of the data section are checked as they are read.
        reader = make_reader(f, validate_crcs=True)
        profile = reader.get_header().profile
        for schema, channel, message in reader.iter_messages(log_time_order=False):
            if channel.message_encoding == "json":
                validator = validators.get(schema.id)
                if validator is None:
                    validator = validators[schema.id] = jsonschema.Draft202012Validator(
                        json.loads(schema.data)
                    )
                decoded = json.loads(message.data)
                seen = channels.get(channel.topic, {}).get("count", 0)
                if limit is None or seen < limit:
                    validator.validate(decoded)
                    validated[channel.topic] = validated.get(channel.topic, 0) + 1
            else:
                decoder = decoders.get(schema.id)
                if decoder is None:
                    decoder = decoders[schema.id] = cdr.decoder_for(
                        channel.message_encoding, schema
                    )
                decoded = decoder(message.data)
            entry = channels.get(channel.topic)
            if entry is None:
                entry = channels[channel.topic] = {
                    "schema": schema.name,
                    "encoding": schema.encoding,
                    "message_encoding": channel.message_encoding,
                    "metadata": dict(channel.metadata),
                    "count": 0,
                    "first_log_time": message.log_time,
                    "hash": hashlib.sha256(),
                }
            entry["last_log_time"] = message.log_time
            values = [str(message.log_time), str(message.publish_time)]
            flatten(decoded, values)
            entry["count"] += 1
            entry["hash"].update((" ".join(values) + "\n").encode())
        metadata = {m.name: dict(m.metadata) for m in reader.iter_metadata()}
        stats = reader.get_summary().statistics
        statistics = {
            "message_start_time": stats.message_start_time,
            "message_end_time": stats.message_end_time,
        }
    # The file read once more from start to end as a stream, every record in turn
    # (no index used), CRCs checked: the messages are all there.
    with open(sys.argv[1], "rb") as f:
        streamed = sum(1 for _ in NonSeekingReader(f, validate_crcs=True).iter_messages())
    for entry in channels.values():
        entry["hash"] = entry["hash"].hexdigest()
    for topic, entry in channels.items():
        entry["validated"] = validated.get(topic, 0)
    json.dump(
        {
            "profile": profile,
            "channels": channels,
            "metadata": metadata,
            "statistics": statistics,
            "streamed": streamed,
        },
        sys.stdout,
    )


main()
