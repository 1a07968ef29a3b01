#!/usr/bin/python3
"""One frame through the proxy, as a browser gets it: WebSocket upgrade at wss://.../ws with the
volume and the access token in the URL (proto/README.md section 1), hello, open the volume, a 64x64
frame, and the renderer that drew it (hello.renderer). The proxy's certificate is self-signed and
not checked. An upgrade without the token must be refused.

usage: one_frame.py PORT TOKEN_FILE VOLUME OUT_JPEG
"""
import json
import ssl
import struct
import sys
import urllib.parse

import websocket  # Debian's python3-websocket


def next_text(ws):
    while True:
        opcode, data = ws.recv_data()
        if opcode == websocket.ABNF.OPCODE_TEXT:
            return json.loads(data)


def main():
    port, token_file, volume, out = sys.argv[1:5]
    with open(token_file) as f:
        token = f.read().strip()
    unverified = {"cert_reqs": ssl.CERT_NONE, "check_hostname": False}
    url = f"wss://127.0.0.1:{port}/ws?" + urllib.parse.urlencode({"volume": volume})
    try:
        websocket.create_connection(url, timeout=60, sslopt=unverified).close()
        sys.exit("an upgrade without the access token was accepted")
    except websocket.WebSocketBadStatusException as refused:
        if refused.status_code != 401:
            sys.exit(f"an upgrade without the access token: HTTP {refused.status_code}, not 401")
    print("access:   an upgrade without the token is refused (401)")
    ws = websocket.create_connection(url + "&" + urllib.parse.urlencode({"token": token}),
                                     timeout=60, sslopt=unverified)
    hello = next_text(ws)
    if hello.get("type") != "hello":
        sys.exit(f"first message is not hello: {hello}")
    renderer = hello["renderer"]
    print(f"hello:    {renderer['renderer']} (software: {renderer['software']})")
    ws.send(json.dumps({"v": 1, "type": "open", "id": 1, "volume": volume}))
    opened = next_text(ws)
    if opened.get("type") != "opened":
        sys.exit(f"open {volume}: {opened}")
    ws.send(json.dumps({"v": 1, "type": "set", "id": 2, "settings": {"size": [64, 64]}}))
    if (ack := next_text(ws)).get("type") != "ack":
        sys.exit(f"set: {ack}")
    ws.send(json.dumps({"v": 1, "type": "render", "id": 3}))
    while True:
        opcode, data = ws.recv_data()
        if opcode == websocket.ABNF.OPCODE_BINARY:
            break
        if json.loads(data).get("type") == "error":
            sys.exit(f"render: {data.decode()}")
    if data[:4] != b"PNBF":
        sys.exit("the binary message is not a frame (no PNBF magic)")
    (header_length,) = struct.unpack_from("<I", data, 6)
    header = json.loads(data[10:10 + header_length])
    image = data[10 + header_length:]
    if header["request"] != 3 or (header["width"], header["height"]) != (64, 64):
        sys.exit(f"not the frame asked for: {header}")
    if not image.startswith(b"\xff\xd8"):
        sys.exit("the frame is not a JPEG image")
    with open(out, "wb") as f:
        f.write(image)
    print(f"frame:    {header['width']}x{header['height']} {header['mode']}, "
          f"{len(image)} bytes -> {out}")
    ws.close()
    if renderer["software"] is not True:
        sys.exit("no GPU here, yet hello does not say the renderer is a software one")


main()
