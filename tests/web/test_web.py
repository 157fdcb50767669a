#!/usr/bin/env python3
"""The web page in headless Chromium (Debian's chromium and chromium-driver, driven over
WebDriver's HTTP API with the standard library only).

  test_web.py --page build-web --bin BUILD/app --out DIR

Serves the page on 127.0.0.1 twice, cross-origin isolated (the threads build) and not (the
single-thread build), and checks from screenshots of the page:
  - the showpiece opens from ?scene=showpiece; the preview pane and the trace pane each match
    raytrace's image of it (mean absolute difference, imgdiff), and neither matches another
    scene's image (so the check can fail);
  - saving the trace and the scene (after a light edit) downloads them: the image matches
    raytrace's of its size, the scene holds the edit and renders;
  - a bad scene picked with the page's file input shows its file:line:col error in red in the
    panel, and the showpiece stays open;
  - files dropped onto the page open; an image picked with "Compare with image" is compared
    with the open scene's reference (raytrace's image of it compares equal);
  - without isolation the page says it traces on one thread, and still traces the showpiece;
  - the frame times (median, p95) and the trace's rays per second of the first run, printed
    for the record.
Exits 1 with a message on the first failed check. Screenshots and crops are left in DIR."""
import argparse
import base64
import json
import os
import re
import shutil
import socket
import struct
import subprocess
import sys
import tempfile
import time
import urllib.request
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
failures = 0

# A drop of two files onto the page, as a user's drag from a file manager makes it.
DROP = '''
    const dt = new DataTransfer();
    dt.items.add(new File([arguments[0]], 'dropped.ray'));
    dt.items.add(new File([arguments[1]], 'part.ray'));
    window.dispatchEvent(new DragEvent('drop', {dataTransfer: dt, bubbles: true}));'''
DROPPED_SCENE = ('#camera 0 2 9  0 -0.2 -1  0 1 0  0.5\n#light_point 4 6 6  1 1 1  1 0 0\n'
                 '#ray_file part.ray\n')
DROPPED_PART = ('#material 0 0 0  0.2 0.2 0.2  0.8 0.2 0.2  0 0 0  1  0 0 0  1  -1 !red!\n'
                '#shape_sphere 0  0 0 0  1\n')


START = time.time()


def check(ok, what):
    global failures
    print(('ok   ' if ok else 'FAIL ') + f'{what} [{time.time() - START:.0f} s]', flush=True)
    if not ok:
        failures += 1


def free_port():
    with socket.socket() as s:
        s.bind(('127.0.0.1', 0))
        return s.getsockname()[1]


def wait_port(port, seconds=20):
    end = time.time() + seconds
    while time.time() < end:
        try:
            with socket.create_connection(('127.0.0.1', port), timeout=1):
                return
        except OSError:
            time.sleep(0.1)
    raise RuntimeError(f'nothing listens on port {port}')


# ---- PNG in, PPM out (Chromium's screenshots: 8-bit RGB or RGBA, not interlaced) ----

def read_png(data):
    assert data[:8] == b'\x89PNG\r\n\x1a\n', 'not a PNG'
    pos, idat = 8, b''
    while pos < len(data):
        n, kind = struct.unpack('>I4s', data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b'IHDR':
            w, h, depth, colour, _, _, interlace = struct.unpack('>IIBBBBB', body)
            assert depth == 8 and colour in (2, 6) and interlace == 0, 'unsupported PNG'
            bpp = 3 if colour == 2 else 4
        elif kind == b'IDAT':
            idat += body
        pos += 12 + n
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows, prev = [], bytearray(stride)
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return w, h, bpp, rows


def crop_ppm(png, x, y, w, h, path):
    _, _, bpp, rows = png
    out = bytearray()
    for row in rows[y:y + h]:
        for i in range(x, x + w):
            out += row[i * bpp:i * bpp + 3]
    with open(path, 'wb') as f:
        f.write(b'P6\n%d %d\n255\n' % (w, h) + bytes(out))


def count_pixels(png, x, y, w, h, test):
    _, _, bpp, rows = png
    n = 0
    for row in rows[y:y + h]:
        for i in range(x, x + w):
            if test(row[i * bpp], row[i * bpp + 1], row[i * bpp + 2]):
                n += 1
    return n


# ---- WebDriver ----

class Browser:
    def __init__(self, driver_port, downloads):
        self.base = f'http://127.0.0.1:{driver_port}'
        args = ['--headless=new', '--no-sandbox', '--disable-gpu', '--disable-quic',
                '--no-first-run', '--disable-background-networking', '--disable-component-update',
                '--disable-sync', '--window-size=1600,900', '--enable-unsafe-swiftshader',
                '--use-angle=swiftshader', '--disable-dev-shm-usage',
                '--user-data-dir=' + tempfile.mkdtemp(prefix='rt-chromium-')]
        caps = {'capabilities': {'alwaysMatch': {
            'browserName': 'chrome',
            'goog:chromeOptions': {'binary': '/usr/bin/chromium', 'args': args}}}}
        self.session = self.call('POST', '/session', caps)['sessionId']
        # What the page downloads lands in that directory (headless Chromium asks for it).
        self.s('POST', '/goog/cdp/execute', {'cmd': 'Browser.setDownloadBehavior', 'params': {
            'behavior': 'allow', 'downloadPath': downloads}})

    def call(self, method, path, body=None):
        data = json.dumps(body).encode() if body is not None else None
        req = urllib.request.Request(self.base + path, data=data, method=method,
                                     headers={'Content-Type': 'application/json'})
        try:
            with urllib.request.urlopen(req, timeout=180) as r:
                return json.loads(r.read())['value']
        except urllib.error.HTTPError as e:
            raise RuntimeError(f'WebDriver {method} {path}: {e.read().decode()[:500]}')

    def s(self, method, path, body=None):
        return self.call(method, f'/session/{self.session}{path}', body)

    def go(self, url):
        self.s('POST', '/url', {'url': url})

    def js(self, script, *args):
        return self.s('POST', '/execute/sync', {'script': script, 'args': list(args)})

    def screenshot(self, path):
        data = base64.b64decode(self.s('GET', '/screenshot'))
        with open(path, 'wb') as f:
            f.write(data)
        return read_png(data)

    def wait(self, script, what, seconds=240):
        end = time.time() + seconds
        while time.time() < end:
            try:
                value = self.js(script)
            except RuntimeError as e:
                # The page's main thread busy past WebDriver's script timeout (a loaded machine:
                # the scene's load, a frame) has not answered yet: asked again, up to `seconds`.
                if '"script timeout"' not in str(e):
                    raise
                value = None
            if value:
                return value
            time.sleep(0.25)
        log = self.js('return (window.rvLog || []).slice(-20).join("\\n")')
        raise RuntimeError(f'timed out waiting for {what}; the page printed:\n{log}')

    def status(self):
        return self.js('return window.rvStatus ? rvStatus() : null')

    def quit(self):
        try:
            self.s('DELETE', '')
        except Exception:
            pass


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--page', required=True)
    ap.add_argument('--bin', required=True, help='the desktop build\'s app/ (raytrace, imgdiff)')
    ap.add_argument('--out', required=True)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    missing = [what for what, ok in (
        (f'the page ({a.page}/index.html: run scripts/build-web.sh)',
         os.path.exists(os.path.join(a.page, 'index.html'))),
        ('chromium', os.path.exists('/usr/bin/chromium')),
        ('chromedriver', shutil.which('chromedriver') is not None)) if not ok]
    if missing:
        print('test_web: skipped, missing ' + ', '.join(missing), file=sys.stderr)
        return 77
    scenes = os.path.join(HERE, '..', '..', 'scenes')
    raytrace, imgdiff = os.path.join(a.bin, 'raytrace'), os.path.join(a.bin, 'imgdiff')

    def render(name, size=None):
        """raytrace's image of scenes/NAME.ray (its default settings, 640x480 unless `size`)."""
        out = os.path.join(a.out, f'{name}-raytrace{"-%dx%d" % size if size else ""}.png')
        flags = ['--width', str(size[0]), '--height', str(size[1])] if size else []
        subprocess.run([raytrace, '-q', os.path.join(scenes, name + '.ray'), *flags, '-o', out],
                       check=True)
        return out

    # What the panes must show, and another scene's image, which they must not match.
    ref, other = render('showpiece'), render('simple')

    def mad(image, reference):
        r = subprocess.run([imgdiff, image, reference], capture_output=True, text=True)
        m = re.search(r'mean abs diff ([0-9.]+) ([0-9.]+) ([0-9.]+)', r.stdout)
        if not m:
            raise RuntimeError('imgdiff printed no mean difference: ' + r.stdout + r.stderr)
        return max(float(v) for v in m.groups())  # the channel that differs most

    isolated, plain, driver = free_port(), free_port(), free_port()
    procs = [subprocess.Popen([sys.executable, os.path.join(HERE, 'serve.py'), '--dir', a.page,
                               '--port', str(isolated)]),
             subprocess.Popen([sys.executable, os.path.join(HERE, 'serve.py'), '--dir', a.page,
                               '--port', str(plain), '--no-isolation']),
             subprocess.Popen(['chromedriver', f'--port={driver}'], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)]
    browser = None
    try:
        for p in (isolated, plain, driver):
            wait_port(p)
        downloads = os.path.join(a.out, 'downloads')
        shutil.rmtree(downloads, ignore_errors=True)
        os.makedirs(downloads)
        browser = Browser(driver, downloads)
        # The pixel's ray tree is printed (inspect) and cleared before the screenshot.
        panes = ('--size 1280x480 --panel off --frames 60',
                 '5 resolution 1;6 wait-spp {spp};7 inspect 288 297;8 inspect clear')

        def open_showpiece(port, tag, spp):
            browser.go(f'http://127.0.0.1:{port}/index.html?scene=showpiece&args={panes[0]}'
                       f'&script={panes[1].format(spp=spp)}')
            browser.wait('return window.rvExitCode !== undefined', f'the {tag} run to end')
            rect = browser.js('const r = document.getElementById("canvas")'
                              '.getBoundingClientRect(); return [r.left, r.top];')
            shot = browser.screenshot(os.path.join(a.out, f'{tag}.png'))
            x0, y0 = int(rect[0]), int(rect[1])
            for i, pane in enumerate(('preview', 'trace')):
                crop_ppm(shot, x0 + 640 * i, y0, 640, 480, os.path.join(a.out, f'{tag}-{pane}.ppm'))
            return browser.status()

        # 1. The threads build, cross-origin isolated: both panes show the showpiece.
        st = open_showpiece(isolated, 'isolated', 8)
        for line in browser.js('return window.rvLog'):  # the run's frame times, for the record
            if re.search(r'frames after start-up|Mray/s', line):
                print('     ' + line, flush=True)
        log = browser.js('return window.rvLog')
        tree = [line for line in log if line.startswith(('camera ray, depth', '  hits ',
                                                            'pixel value'))]
        check(len(tree) == 3 and 'showpiece.ray' in ''.join(log) and
              re.search(r'  hits .* at .*\.ray:\d+:\d+', tree[1]),
              'inspect prints the pixel\'s ray tree in the page: ' + ' | '.join(tree)[:160])
        check(browser.js('return window.rvThreads') is True and st['threaded'],
              f'the isolated page runs the threads build ({st["threads"]} threads)')
        check(st['scene'].endswith('/showpiece.ray') and st['spp'] >= 8,
              f'?scene=showpiece opened it and traced {st["spp"]} spp')
        limits = {'preview': 12, 'trace': 4}
        for pane, limit in limits.items():
            crop = os.path.join(a.out, f'isolated-{pane}.ppm')
            near, far = mad(crop, ref), mad(crop, other)
            check(near <= limit and far > 2 * limit,
                  f'the {pane} pane shows the showpiece (mean difference {near:.1f} of 255 '
                  f'against raytrace\'s image, at most {limit}; {far:.1f} against another scene)')

        # 2. Saving downloads: the trace pane's image, then the scene with its first light edited
        # (relative names, as the panel's: beside the open scene).
        saves = ('2 wait-spp 4;3 save-image showpiece-trace.png;'
                 '4 light 0 colour 0.2 0.9 0.3;5 save-scene showpiece-edited.ray')
        browser.go(f'http://127.0.0.1:{isolated}/index.html?scene=showpiece&script={saves}')
        browser.wait('return window.rvExitCode !== undefined', 'the saving run to end')
        got = {}
        end = time.time() + 120
        while len(got) < 2 and time.time() < end:
            for name in ('showpiece-trace.png', 'showpiece-edited.ray'):
                path = os.path.join(downloads, name)
                if os.path.exists(path) and name not in got:
                    got[name] = path
            time.sleep(0.25)
        check(len(got) == 2, f'saving downloads the files ({", ".join(sorted(got)) or "none"})')
        if 'showpiece-trace.png' in got:
            trace = got['showpiece-trace.png']
            with open(trace, 'rb') as f:
                tw, th = read_png(f.read())[:2]
            # raytrace's image of the same size: the download is the trace, not another image.
            near = mad(trace, render('showpiece', (tw, th)))
            far = mad(trace, render('simple', (tw, th)))
            check(near <= 12 and far > 24, f'the downloaded image is the trace ({tw}x{th}, mean '
                  f'difference {near:.1f} against raytrace\'s image, {far:.1f} against another)')
        if 'showpiece-edited.ray' in got:
            # Beside the scene's parts and textures, the downloaded scene renders, with the edit.
            edited = os.path.join(a.out, 'edited')
            shutil.rmtree(edited, ignore_errors=True)
            for sub in ('parts', 'textures'):
                shutil.copytree(os.path.join(scenes, sub), os.path.join(edited, sub))
            shutil.copy(got['showpiece-edited.ray'], edited)
            with open(got['showpiece-edited.ray']) as f:
                text = f.read()
            r = subprocess.run([raytrace, '-q', os.path.join(edited, 'showpiece-edited.ray'),
                                '--width', '64', '--height', '48', '-o',
                                os.path.join(edited, 'edited.png')], capture_output=True, text=True)
            check(re.search(r'#light_spot 0\.2 0\.9 0\.3 ', text) is not None and r.returncode == 0,
                  'the downloaded scene holds the edited light and renders '
                  f'({r.stderr.strip() or "raytrace: ok"})')

        # 3. A bad scene, picked with the page's file input: its error in red, the showpiece kept.
        browser.go(f'http://127.0.0.1:{isolated}/index.html?scene=showpiece')
        browser.wait('const s = window.rvStatus && rvStatus(); return s && s.spp >= 1',
                     'the showpiece to trace')
        bad = os.path.join(a.out, 'bad.ray')
        with open(bad, 'w') as f:
            f.write('#camera 0 0 5  0 0 -1  0 1 0  0.5\n#sphere 0 0 0\n')
        before = browser.screenshot(os.path.join(a.out, 'before-error.png'))
        field = browser.s('POST', '/element', {'using': 'css selector', 'value': '#files'})
        element = next(iter(field.values()))
        browser.s('POST', f'/element/{element}/value', {'text': bad})
        st = browser.wait('const s = rvStatus(); return s && s.error ? s : null', 'the error')
        shot = browser.screenshot(os.path.join(a.out, 'error.png'))
        check(re.match(r'^/uploads/1/bad\.ray:\d+:\d+: error: ', st['message']) is not None,
              f'the bad scene\'s error names file:line:col ({st["message"].splitlines()[0]})')
        check(st['scene'].endswith('/showpiece.ray'), 'the showpiece stays open')
        reddish = lambda r, g, b: r > 200 and 80 < g < 140 and 80 < b < 140
        w, h = shot[0], shot[1]
        red_after = count_pixels(shot, 0, 0, w // 3, h, reddish)
        red_before = count_pixels(before, 0, 0, w // 3, h, reddish)
        check(red_after > 100 + red_before,
              f'the panel shows the error in red ({red_after} red pixels, {red_before} before)')

        # A folder picked with "Open folder...": its scene opens with its included parts.
        folder = os.path.join(a.out, 'picked')
        shutil.rmtree(folder, ignore_errors=True)
        for sub in ('parts', 'textures'):  # groups.ray's parts, and their texture
            shutil.copytree(os.path.join(scenes, sub), os.path.join(folder, sub))
        shutil.copy(os.path.join(scenes, 'groups.ray'), folder)
        field = browser.s('POST', '/element', {'using': 'css selector', 'value': '#folder'})
        browser.s('POST', f'/element/{next(iter(field.values()))}/value', {'text': folder})
        st = browser.wait('const s = rvStatus(); return s.scene.endsWith("/groups.ray") && '
                          '!s.loading ? s : null', "the picked folder's scene")
        check(st['scene'] == '/uploads/2/picked/groups.ray' and not st['error'],
              f'a picked folder opens its scene with its parts ({st["scene"]})')
        # Files dropped onto the page: a scene and the file it includes.
        browser.js(DROP, DROPPED_SCENE, DROPPED_PART)
        st = browser.wait('const s = rvStatus(); return s.scene.endsWith("/dropped.ray") && '
                          '!s.loading ? s : null', 'the dropped scene')
        check(not st['error'], 'files dropped onto the page open, the included one with them '
                               f'({st["scene"]} {st["message"]})')
        # "Compare with image…": raytrace's image of that scene is the reference's (WebAssembly's
        # libm may round a few pixels to the next 8-bit step; none is off by more than 8).
        folder = os.path.join(a.out, 'compare')
        os.makedirs(folder, exist_ok=True)
        for name, text in (('dropped.ray', DROPPED_SCENE), ('part.ray', DROPPED_PART)):
            with open(os.path.join(folder, name), 'w') as f:
                f.write(text)
        theirs = os.path.join(folder, 'theirs.png')
        subprocess.run([raytrace, '-q', os.path.join(folder, 'dropped.ray'), '--width', '80',
                        '--height', '60', '-o', theirs], check=True)
        field = browser.s('POST', '/element', {'using': 'css selector', 'value': '#compare-file'})
        browser.s('POST', f'/element/{next(iter(field.values()))}/value', {'text': theirs})
        st = browser.wait('const s = rvStatus(); return s.compare.includes("mean |diff|") && '
                          '!s.compare.includes("rendering") ? s : null', 'the comparison')
        m = re.search(r'mean \|diff\| ([0-9.]+) .*, ([0-9.]+)% off', st['compare'])
        check(m and float(m.group(1)) < 0.5 and float(m.group(2)) == 0,
              f'an image picked with "Compare with image" is compared ({st["compare"]})')

        # 4. Not isolated: the single-thread build, with a note, traces the showpiece too.
        st = open_showpiece(plain, 'single', 4)
        note = browser.js('return document.getElementById("note").textContent')
        check(browser.js('return window.rvThreads') is False and not st['threaded'] and
              'one thread' in note, 'without isolation the page says it traces on one thread')
        crop = os.path.join(a.out, 'single-trace.ppm')
        near = mad(crop, ref)
        check(near <= limits['trace'] and st['spp'] >= 4,
              f'and its trace shows the showpiece ({st["spp"]} spp, mean difference {near:.1f})')

    finally:
        if browser:
            browser.quit()
        for p in procs:
            p.terminate()
    if failures:
        print(f'test_web: {failures} checks failed', file=sys.stderr)
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main())
