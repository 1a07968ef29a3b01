#!/usr/bin/python3
"""Validates protocol messages against the JSON Schemas in proto/v1 (draft 2020-12).

    validate_messages.py PROTO_V1_DIR [SENT.jsonl ...] [--examples EXAMPLES_V1_DIR]

Each JSONL line is {"kind": "text" | "frame_header", "message": {...}}: what the server sends.
Text messages are checked against the schema their "type" names, frame headers against
frame_header.schema.json. Every schema's own examples (JSON Schema's `examples`, at its root or in
`$defs/request` and `$defs/response`) must pass the schema that holds them, and each client message
type needs at least one. With --examples, every examples/v1/valid/*.json must pass the schema of
its client message type, and every examples/v1/invalid/*.json must fail it, except the few whose
error the schemas cannot express (NOT_EXPRESSIBLE below), which must pass it instead so that the
list stays exact. Prints every failure; exits 1 if there was any.

Which schema checks a message follows from the schemas themselves: each names the type it checks
(`properties.type`, a const or an enum) at its root, or in `$defs/request` and `$defs/response`
where one file serves both directions (stats); the types in common.schema.json's
`$defs/client_type` are the client's, the others the server's. A new message needs its schema
only.

Needs the jsonschema package (Debian python3-jsonschema, 4.10): run it with /usr/bin/python3.
"""

import argparse
import json
import math
import pathlib
import sys
import warnings

import jsonschema

# Invalid examples that the C++ rejects but JSON Schema cannot: each must PASS schema validation.
NOT_EXPRESSIBLE = {
    # eye == target is a relation between two members (or with the session's current target).
    "camera_eye_equals_target",
    # A zero direction is invalid only for a directional light, possibly set by an earlier patch.
    "light_zero_direction",
    # Ordering between array items (positions must not decrease) has no keyword.
    "tf_decreasing_x",
    # JSON Schema's "integer" admits 512.0; the server wants integers written without a fraction.
    "size_written_as_float",
}

FRAME_HEADER_SCHEMA = ("frame_header.schema.json", "")


def strict_loads(text):
    """json.loads that, like the server, rejects NaN, Infinity and numbers beyond double range."""

    def no_constant(name):
        raise ValueError(f"{name} is not JSON")

    def finite_float(token):
        value = float(token)
        if not math.isfinite(value):
            raise ValueError(f"{token} is not a finite number")
        return value

    return json.loads(text, parse_constant=no_constant, parse_float=finite_float)


def named_types(part):
    """The message types a (sub)schema checks: its `type` member's const or enum."""
    member = part.get("properties", {}).get("type", {}) if isinstance(part, dict) else {}
    if "const" in member:
        return [member["const"]]
    return list(member.get("enum", []))


class Schemas:
    def __init__(self, folder):
        self.store = {}
        self.by_file = {}
        for path in sorted(pathlib.Path(folder).glob("*.schema.json")):
            schema = json.loads(path.read_text(encoding="utf-8"))
            jsonschema.Draft202012Validator.check_schema(schema)
            self.store[schema["$id"]] = schema
            self.by_file[path.name] = schema
        self.validators = {}
        self.client, self.server = self.schemas_by_type()

    def schemas_by_type(self):
        """{type: (file, pointer)} for client and for server messages, read from the schemas."""
        common = self.by_file.get("common.schema.json", {})
        client_types = set(common.get("$defs", {}).get("client_type", {}).get("enum", []))
        self.client_types = client_types
        client, server = {}, {}
        for file, schema in self.by_file.items():
            defs = schema.get("$defs", {})
            for name in named_types(schema):
                (client if name in client_types else server)[name] = (file, "")
            for name in named_types(defs.get("request")):
                client[name] = (file, "/$defs/request")
            for name in named_types(defs.get("response")):
                server[name] = (file, "/$defs/response")
        return client, server

    def validator(self, key):
        if key not in self.validators:
            file, pointer = key
            schema = self.by_file[file]
            part = schema
            for token in filter(None, pointer.split("/")):
                part = part[token]
            with warnings.catch_warnings():
                # RefResolver is deprecated from jsonschema 4.18 on; 4.10 has nothing else.
                warnings.simplefilter("ignore", DeprecationWarning)
                resolver = jsonschema.RefResolver(base_uri=schema["$id"], referrer=schema,
                                                  store=self.store)
            self.validators[key] = jsonschema.Draft202012Validator(part, resolver=resolver)
        return self.validators[key]

    def errors(self, key, instance):
        """Sorted messages of every violation, each prefixed with the instance's JSON pointer."""
        return sorted(pointer + ": " + message for pointer, message in self.located(key, instance))

    def located(self, key, instance):
        """(JSON pointer, message) of every violation."""
        return [("/" + "/".join(str(p) for p in e.absolute_path), e.message)
                for e in self.validator(key).iter_errors(instance)]


def check_schema_examples(schemas, failures):
    """Checks each schema's `examples` against the part of the schema that holds them."""
    count = 0
    with_examples = set()
    for file, schema in sorted(schemas.by_file.items()):
        defs = schema.get("$defs", {})
        parts = [("", schema), ("/$defs/request", defs.get("request")),
                 ("/$defs/response", defs.get("response"))]
        for pointer, part in parts:
            if not isinstance(part, dict) or "examples" not in part:
                continue
            with_examples.add((file, pointer))
            for number, example in enumerate(part["examples"]):
                for error in schemas.errors((file, pointer), example):
                    failures.append(f"{file}#{pointer}/examples/{number}: example rejected by "
                                    f"its schema: {error}")
                count += 1
    for name, key in sorted(schemas.client.items()):
        if key not in with_examples:
            failures.append(f"{key[0]}{key[1]}: the client message {name!r} has no examples")
    return count


def within(pointer, ancestor):
    """Whether `pointer` is `ancestor` or lies inside it ("/" is the whole message)."""
    return ancestor == "/" or pointer == ancestor or pointer.startswith(ancestor + "/")


def client_schema_for(schemas, message):
    if not isinstance(message, dict) or not isinstance(message.get("type"), str):
        return None
    return schemas.client.get(message["type"])


def check_sent(schemas, path, failures):
    count = 0
    lines = pathlib.Path(path).read_text(encoding="utf-8").splitlines()
    for number, line in enumerate(lines, 1):
        if not line.strip():
            continue
        where = f"{path}:{number}"
        try:
            entry = strict_loads(line)
        except ValueError as e:
            failures.append(f"{where}: not JSON: {e}")
            continue
        message = entry.get("message") if isinstance(entry, dict) else None
        kind = entry.get("kind") if isinstance(entry, dict) else None
        if kind == "frame_header":
            key = FRAME_HEADER_SCHEMA
        elif kind == "text" and isinstance(message, dict):
            key = schemas.server.get(message.get("type"))
            if key is None:
                failures.append(f"{where}: no schema for server message type "
                                f"{message.get('type')!r}")
                continue
        else:
            failures.append(f"{where}: expected {{\"kind\": \"text\"|\"frame_header\", "
                            f"\"message\": {{...}}}}")
            continue
        for error in schemas.errors(key, message):
            failures.append(f"{where} ({key[0]}{key[1]}): {error}")
        count += 1
    if count == 0:
        failures.append(f"{path}: no messages")
    return count


def check_examples(schemas, folder, failures):
    valid = sorted((pathlib.Path(folder) / "valid").glob("*.json"))
    invalid = sorted((pathlib.Path(folder) / "invalid").glob("*.json"))
    if not valid or not invalid:
        failures.append(f"{folder}: expected examples in valid/ and invalid/")
    for path in valid:
        message = strict_loads(path.read_text(encoding="utf-8"))
        key = client_schema_for(schemas, message)
        if key is None:
            failures.append(f"{path}: valid example has no client message type")
            continue
        for error in schemas.errors(key, message):
            failures.append(f"{path} ({key[0]}{key[1]}): valid example rejected: {error}")
    seen_exclusions = set()
    for path in invalid:
        entry = json.loads(path.read_text(encoding="utf-8"))
        name = path.stem
        if set(entry) not in ({"message", "code", "field"}, {"raw", "code", "field"}):
            failures.append(f"{path}: expected message or raw, code and field")
            continue
        # The expected error must itself be a valid error message.
        expected = {"v": 1, "type": "error", "code": entry["code"], "message": "",
                    "field": entry["field"]}
        for error in schemas.errors(schemas.server["error"], expected):
            failures.append(f"{path}: expected error is not a valid error message: {error}")
        if "raw" in entry:
            try:
                message = strict_loads(entry["raw"])
            except ValueError:
                rejected_by = "JSON parsing"
            else:
                failures.append(f"{path}: raw text is valid JSON; give it as \"message\"")
                continue
        else:
            message = entry["message"]
            key = client_schema_for(schemas, message)
            if key is None:
                rejected_by = "schema selection (not an object with a client type)"
            else:
                errors = schemas.located(key, message)
                rejected_by = f"{key[0]}{key[1]}" if errors else None
                # A schema reports a missing or unknown member at its parent object and a failed
                # oneOf at the object it applies to: one error must be at the field or above it.
                if errors and not any(within(entry["field"], at) for at, _ in errors):
                    failures.append(f"{path}: rejected by {rejected_by}, but not at "
                                    f"{entry['field']} or above it: {sorted(errors)}")
        if name in NOT_EXPRESSIBLE:
            seen_exclusions.add(name)
            if rejected_by is not None:
                failures.append(f"{path}: listed as not expressible in schema, but rejected by "
                                f"{rejected_by}: remove it from NOT_EXPRESSIBLE")
            else:
                print(f"note: {name}: {entry['code']} at {entry['field']} is checked by the "
                      f"C++ only (not expressible in JSON Schema)")
        elif rejected_by is None:
            failures.append(f"{path}: invalid example ({entry['code']} at {entry['field']}) "
                            f"passes schema validation")
    for name in sorted(NOT_EXPRESSIBLE - seen_exclusions):
        failures.append(f"NOT_EXPRESSIBLE names {name}, which is not an invalid example")
    return len(valid), len(invalid)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("proto_v1", help="the proto/v1 folder with the *.schema.json files")
    parser.add_argument("jsonl", nargs="*", help="server messages, one JSON object a line")
    parser.add_argument("--examples", help="the proto/examples/v1 folder to check as well")
    args = parser.parse_args()
    if not args.jsonl and not args.examples:
        parser.error("give JSONL files, --examples or both")

    failures = []
    schemas = Schemas(args.proto_v1)
    if not schemas.by_file:
        failures.append(f"{args.proto_v1}: no *.schema.json files")
    for name in sorted(schemas.client_types - set(schemas.client)):
        failures.append(f"{args.proto_v1}: no schema names the client message type {name!r}")
    count = check_schema_examples(schemas, failures)
    print(f"{args.proto_v1}: {count} examples in the schemas checked")
    for path in args.jsonl:
        count = check_sent(schemas, path, failures)
        print(f"{path}: {count} server messages checked")
    if args.examples:
        valid, invalid = check_examples(schemas, args.examples, failures)
        print(f"{args.examples}: {valid} valid and {invalid} invalid examples checked")
    for failure in failures:
        print("FAIL: " + failure, file=sys.stderr)
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
