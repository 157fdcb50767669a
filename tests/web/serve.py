#!/usr/bin/env python3
"""A static file server for the web page (scripts/serve-web.sh, tests/web/test_web.py).

Every response carries the cross-origin isolation headers (the page's threads need them),
unless --no-isolation, which the test uses to see the single-thread page. .wasm goes out as
application/wasm, for streaming compilation."""
import argparse
import functools
import http.server
import sys


class Handler(http.server.SimpleHTTPRequestHandler):
    isolated = True
    extensions_map = {**http.server.SimpleHTTPRequestHandler.extensions_map,
                      '.wasm': 'application/wasm', '.js': 'text/javascript',
                      '.data': 'application/octet-stream'}

    def end_headers(self):
        if self.isolated:
            self.send_header('Cross-Origin-Opener-Policy', 'same-origin')
            self.send_header('Cross-Origin-Embedder-Policy', 'require-corp')
        self.send_header('Cache-Control', 'no-cache')
        super().end_headers()

    def log_message(self, format, *args):  # quiet: errors only
        if args and str(args[1]).startswith(('4', '5')):
            super().log_message(format, *args)


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument('--dir', required=True)
    ap.add_argument('--bind', default='127.0.0.1')
    ap.add_argument('--port', type=int, default=8000)
    ap.add_argument('--no-isolation', action='store_true')
    a = ap.parse_args()
    Handler.isolated = not a.no_isolation
    handler = functools.partial(Handler, directory=a.dir)
    server = http.server.ThreadingHTTPServer((a.bind, a.port), handler)
    print(f'serving {a.dir} on http://{a.bind}:{server.server_address[1]}/', file=sys.stderr,
          flush=True)
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        pass


if __name__ == '__main__':
    main()
