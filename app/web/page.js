// The page around rayview's WebAssembly program: chooses the threads build when the page is
// cross-origin isolated (else the single-thread one, with a note), passes ?scene=NAME and
// ?args=... as the command line, puts picked and dropped files (folders too) into the program's
// in-memory file system and opens the scene among them, and downloads what the viewer saves.
'use strict';

const params = new URLSearchParams(location.search);
const threads = self.crossOriginIsolated === true;
const note = document.getElementById('note');
const statusLine = document.getElementById('status');
if (!threads) {
  note.textContent = 'Not cross-origin isolated: the trace runs on one thread. Serve the page ' +
      'with scripts/serve-web.sh, or with the headers Cross-Origin-Opener-Policy: same-origin ' +
      'and Cross-Origin-Embedder-Policy: require-corp, for every core.';
  note.title = note.textContent;
  document.getElementById('hint').style.display = 'none';
}

// The command line: rayview's options (?args=--spp%2064), a script (?script=5 orbit 10 0;6
// wait-spp 8: lines split at ';', as --script FILE), then the scene: ?scene=NAME opens
// scenes/NAME.ray of the samples, ?scene=/path any file of the file system; none: the showpiece.
const scriptFile = '/tmp/page-script.txt';
function commandLine() {
  const args = (params.get('args') || '').split(' ').filter((a) => a.length > 0);
  if (params.get('script')) args.push('--script', scriptFile);
  // --size WxH: the canvas takes that size in device pixels (else it fills the page).
  const size = args.indexOf('--size');
  if (size >= 0 && /^\d+x\d+$/.test(args[size + 1] || '')) {
    const [w, h] = args[size + 1].split('x').map(Number);
    // A style sheet rule, not the canvas's own style, which Emscripten's GLFW resets.
    const ratio = window.devicePixelRatio || 1;
    const rule = document.createElement('style');
    rule.textContent = `#canvas { width: ${w / ratio}px; height: ${h / ratio}px; }`;
    document.head.appendChild(rule);
  }
  const scene = params.get('scene');
  if (scene) args.push(scene.startsWith('/') ? scene : '/data/scenes/' + scene.replace(/\.ray$/, '') + '.ray');
  return args;
}

const log = [];  // what the program printed (the page's test reads it)
var Module = {
  canvas: document.getElementById('canvas'),
  arguments: commandLine(),
  print: (text) => { log.push(text); console.log(text); },
  printErr: (text) => { log.push(text); console.warn(text); },
  setStatus: (text) => { statusLine.textContent = text; },
  preRun: [() => {
    if (params.get('script'))
      Module.FS.writeFile(scriptFile, params.get('script').split(';').join('\n') + '\n');
  }],
  onRuntimeInitialized: () => {
    statusLine.style.display = 'none';
    window.rvReady = true;
  },
  // A file the viewer saved: downloaded under its name.
  rvDownload: (path) => {
    const data = Module.FS.readFile(path);
    const url = URL.createObjectURL(new Blob([data]));
    const a = document.createElement('a');
    a.href = url;
    a.download = path.split('/').pop();
    document.body.appendChild(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(url), 10000);
  },
  rvFinished: (code) => { window.rvExitCode = code; },
};
window.rvLog = log;
// A failure of the program itself (an abort, an exception that escaped) is shown on the page.
function fatal(text) {
  log.push('fatal: ' + text);
  statusLine.style.display = 'flex';
  statusLine.textContent = 'rayview stopped: ' + text;
}
Module.onAbort = (what) => fatal(String(what));
window.addEventListener('error', (e) => fatal(e.message + (e.error && e.error.stack ? '\n' + e.error.stack : '')));
window.addEventListener('unhandledrejection', (e) => fatal(String(e.reason)));
window.rvThreads = threads;
// The viewer's state (rv_status in app/rayview/web.cpp), null until the program runs.
window.rvStatus = () =>
    window.rvReady ? JSON.parse(Module.ccall('rv_status', 'string', [], [])) : null;
window.rvOpen = (path) => Module.ccall('rv_open', null, ['string'], [path]);

// ---- files into the program's file system ----

let uploads = 0;
function mkdirs(FS, path) {
  let dir = '';
  for (const part of path.split('/').slice(1, -1)) {
    dir += '/' + part;
    try { FS.mkdir(dir); } catch (e) { /* exists */ }
  }
}

// The scene to open among the files: a .ray file no other one names (the others are included),
// the shallowest first; null without one.
function sceneAmong(files) {
  const rays = files.filter((f) => /\.ray$/i.test(f.path));
  const named = (f) => rays.some((g) => g !== f && g.text.includes(f.path.split('/').pop()));
  const order = (a, b) => a.path.split('/').length - b.path.split('/').length ||
                          a.path.localeCompare(b.path);
  const top = rays.filter((f) => !named(f)).sort(order);
  return (top.length ? top : rays.sort(order))[0] || null;
}

// `entries`: [{path: 'folder/name', file: File}]. Written under /uploads/N/, then opened.
async function openFiles(entries) {
  if (!entries.length) return;
  const FS = Module.FS;
  const root = '/uploads/' + (++uploads);
  const files = [];
  for (const {path, file} of entries) {
    const full = root + '/' + path;
    const bytes = new Uint8Array(await file.arrayBuffer());
    mkdirs(FS, full);
    FS.writeFile(full, bytes);
    files.push({path: full, text: /\.ray$/i.test(path) ? new TextDecoder().decode(bytes) : ''});
  }
  const scene = sceneAmong(files);
  // Images alone are compared with the open scene's reference (the viewer takes an image's
  // path as a comparison, the comparison pane).
  const image = files.find((f) => /\.(png|bmp|ppm|jpe?g|pfm|exr)$/i.test(f.path));
  if (scene) rvOpen(scene.path);
  else if (image) rvOpen(image.path);
  else note.textContent = 'No .ray file among the ' + files.length + ' files given.';
}

function picked(input) {
  const entries = [...input.files].map((f) => ({path: f.webkitRelativePath || f.name, file: f}));
  input.value = '';
  openFiles(entries);
}
const filesInput = document.getElementById('files');
const folderInput = document.getElementById('folder');
const compareInput = document.getElementById('compare-file');
document.getElementById('compare').onclick = () => compareInput.click();
compareInput.onchange = () => picked(compareInput);
document.getElementById('open-files').onclick = () => filesInput.click();
document.getElementById('open-folder').onclick = () => folderInput.click();
filesInput.onchange = () => picked(filesInput);
folderInput.onchange = () => picked(folderInput);

// Drag and drop of files and folders (a folder's files keep their relative paths, so its
// includes and textures are found). Captured before GLFW's own handler, which flattens folders.
async function walk(entry, prefix, out) {
  if (entry.isFile) {
    out.push({path: prefix + entry.name, file: await new Promise((ok, no) => entry.file(ok, no))});
  } else if (entry.isDirectory) {
    const reader = entry.createReader();
    for (;;) {
      const batch = await new Promise((ok, no) => reader.readEntries(ok, no));
      if (!batch.length) break;
      for (const e of batch) await walk(e, prefix + entry.name + '/', out);
    }
  }
}
window.addEventListener('dragover', (e) => {
  e.preventDefault();
  e.stopPropagation();
  document.body.classList.add('dragging');
}, true);
window.addEventListener('dragleave', () => document.body.classList.remove('dragging'), true);
window.addEventListener('drop', async (e) => {
  e.preventDefault();
  e.stopPropagation();
  document.body.classList.remove('dragging');
  const items = [...e.dataTransfer.items].filter((i) => i.kind === 'file');
  const entries = items.map((i) => i.webkitGetAsEntry && i.webkitGetAsEntry()).filter((x) => x);
  const out = [];
  for (const entry of entries) await walk(entry, '', out);
  if (!out.length)  // no entries (a browser without them): the files, without folders
    for (const file of e.dataTransfer.files) out.push({path: file.name, file});
  openFiles(out);
}, true);

// The program: WebAssembly threads need the isolation; the single-thread build runs anywhere.
const script = document.createElement('script');
script.src = threads ? 'rayview.js' : 'rayview-single.js';
document.body.appendChild(script);
