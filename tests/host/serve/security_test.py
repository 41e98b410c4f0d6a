#!/usr/bin/python3
"""palpa serve's security rules, each tried against a real server in front of palpa-sim: Host and
Origin checked on every HTTP request and WebSocket upgrade, and a non-loopback listener that
refuses everything without its token. Usage: security_test.py PALPA PALPA_SIM"""
import asyncio
import sys

import websockets

from harness import Serve, Sim, fail, http, upgrade_lines


def check(what, got, expected):
    if got != expected:
        fail(f"{what}: HTTP {got}, expected {expected}")
    print(f"ok  {what}: HTTP {got}")


def loopback_rules(serve):
    port, own = serve.port, serve.authority
    get = lambda host, *extra: http(port, ["GET / HTTP/1.1", f"Host: {host}", "Connection: close",
                                           *extra])[0]
    check("GET / by 127.0.0.1", get(own), 200)
    check("GET / by localhost", get(f"localhost:{port}"), 200)
    check("GET / by [::1]", get(f"[::1]:{port}"), 200)
    check("GET / naming a DNS-rebinding host", get(f"attacker.example:{port}"), 403)
    check("GET / naming another port", get(f"127.0.0.1:{port + 1 if port < 65535 else 1}"), 403)
    check("GET / naming no port", get("127.0.0.1"), 403)
    check("GET / naming a LAN address on a loopback listener", get(f"192.168.1.5:{port}"), 403)
    check("GET / from another site's page", get(own, "Origin: http://attacker.example"), 403)
    check("GET / from an opaque origin", get(own, "Origin: null"), 403)
    check("GET / from the page itself", get(own, f"Origin: http://{own}"), 200)
    status = http(port, ["GET / HTTP/1.0"])[0]
    check("GET / without Host", status, 400)
    check("GET of a file outside the page",
          http(port, ["GET /../../etc/passwd HTTP/1.1", f"Host: {own}", "Connection: close"])[0],
          404)
    check("POST /", http(port, ["POST / HTTP/1.1", f"Host: {own}", "Content-Length: 0",
                                "Connection: close"])[0], 405)
    up = lambda host, origin: http(port, upgrade_lines(host, origin))[0]
    check("upgrade from the page", up(own, f"http://{own}"), 101)
    check("upgrade by a script (no Origin)", up(own, None), 101)
    check("upgrade from another site's page", up(own, "http://attacker.example"), 403)
    check("upgrade from another site on a loopback port", up(own, "http://127.0.0.1:1"), 403)
    check("upgrade from an https page of another site", up(own, "https://attacker.example"), 403)
    check("upgrade naming a DNS-rebinding host", up(f"attacker.example:{port}",
                                                    f"http://attacker.example:{port}"), 403)
    check("upgrade elsewhere than /websocket",
          http(port, upgrade_lines(own, None, target="/other"))[0], 404)

    async def library_refused():
        try:
            async with websockets.connect(serve.url, origin="http://attacker.example"):
                fail("a page from another origin opened the WebSocket")
        except websockets.InvalidStatusCode as e:
            check("python3-websockets from another origin", e.status_code, 403)
    asyncio.run(library_refused())
    if "refused" not in serve.log():
        fail("refusals are not logged")


def token_rules(serve):
    port, own = serve.port, serve.authority
    if not serve.token or len(serve.token) != 32:
        fail(f"a non-loopback listener printed no 128-bit token: {serve.token!r}")
    get = lambda target, *extra: http(port, [f"GET {target} HTTP/1.1", f"Host: {own}",
                                             "Connection: close", *extra])
    check("beyond loopback: GET / without the token", get("/")[0], 401)
    check("beyond loopback: GET / with a wrong token", get("/?token=" + "0" * 32)[0], 401)
    check("beyond loopback: GET / with a token one digit short", get("/?token=" + serve.token[:-1])[0], 401)
    status, headers, _ = get("/?token=" + serve.token)
    check("beyond loopback: GET / with the token", status, 200)
    cookie = headers.get("set-cookie", "")
    if serve.token not in cookie or "HttpOnly" not in cookie or "SameSite=Strict" not in cookie:
        fail(f"the token is not kept as a strict, HttpOnly cookie: {cookie!r}")
    check("beyond loopback: GET with the cookie", get("/", f"Cookie: palpa_token={serve.token}")[0], 200)
    check("beyond loopback: GET with the bearer header",
          get("/", f"Authorization: Bearer {serve.token}")[0], 200)
    check("beyond loopback: a LAN address as Host",
          http(port, ["GET /?token=" + serve.token + " HTTP/1.1", f"Host: 10.1.2.3:{port}",
                      "Connection: close"])[0], 200)
    check("beyond loopback: a DNS name as Host, even with the token",
          http(port, ["GET /?token=" + serve.token + " HTTP/1.1", f"Host: lab.example:{port}",
                      "Connection: close"])[0], 403)
    check("beyond loopback: upgrade without the token", http(port, upgrade_lines(own))[0], 401)
    check("beyond loopback: upgrade with the token",
          http(port, upgrade_lines(own, target="/websocket?token=" + serve.token))[0], 101)


def main():
    palpa, palpa_sim = sys.argv[1], sys.argv[2]
    sim = Sim(palpa_sim)
    try:
        serve = Serve(palpa, sim.address)
        try:
            loopback_rules(serve)
        finally:
            serve.close()
        serve = Serve(palpa, sim.address, listen="0.0.0.0:0")
        try:
            token_rules(serve)
        finally:
            serve.close()
    finally:
        sim.close()
    print("security_test: every rule held")


if __name__ == "__main__":
    main()
