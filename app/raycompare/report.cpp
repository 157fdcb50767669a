#include "report.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>

#include "rt/util/text.h"

namespace raycompare {

namespace {

// A row's diagnosis, each of its lines escaped() and joined by `sep` (a terminal's line break and
// indent, a page's <br>: the escaping would show a newline as \x0a).
std::string diagnosis_text(const Row& r, const std::string& sep) {
    std::string out;
    size_t start = 0;
    while (start <= r.diagnosis.size()) {
        const size_t end = std::min(r.diagnosis.find('\n', start), r.diagnosis.size());
        out += (start ? sep : "") + escaped(r.diagnosis.substr(start, end - start));
        start = end + 1;
    }
    return out;
}

// v with `digits` decimals, or in %g's shortest form (digits < 0).
std::string num(double v, int digits = -1) {
    char buf[64];
    if (digits < 0)
        std::snprintf(buf, sizeof buf, "%.6g", v);
    else
        std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

std::string size_text(const Row& r) {
    return std::to_string(r.width) + "x" + std::to_string(r.height);
}

// A CSV field, quoted when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& s) {
    if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

std::string html_escape(const std::string& s) {
    std::string o;
    for (char c : s) {
        switch (c) {
            case '&':
                o += "&amp;";
                break;
            case '<':
                o += "&lt;";
                break;
            case '>':
                o += "&gt;";
                break;
            case '"':
                o += "&quot;";
                break;
            default:
                o += c;
        }
    }
    return o;
}

// A JSON string: quotes, backslashes and control bytes escaped (the text is escaped() UTF-8).
std::string json_string(const std::string& s) {
    std::string o = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') {
            o += '\\';
            o += c;
        } else if (c == '\n') {
            o += "\\n";
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
            o += buf;
        } else {
            o += c;
        }
    }
    return o + "\"";
}

// A word for a POSIX shell: as it is when it is plain, else in single quotes.
std::string shell_word(const std::string& s) {
    const bool plain = !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) ||
               std::string_view("_./-+,:=@%").find(c) != std::string_view::npos;
    });
    if (plain) return s;
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// The row's name as shown (escaped): the student's, else the path.
std::string shown_name(const Row& r) { return escaped(r.name.empty() ? r.path : r.name); }

// A code point of East Asian wide or fullwidth forms, or an emoji: two columns.
bool wide(char32_t c) {
    return (c >= 0x1100 && c <= 0x115F) || (c >= 0x2E80 && c <= 0x303E) ||
           (c >= 0x3041 && c <= 0x33FF) || (c >= 0x3400 && c <= 0x4DBF) ||
           (c >= 0x4E00 && c <= 0x9FFF) || (c >= 0xA000 && c <= 0xA4CF) ||
           (c >= 0xAC00 && c <= 0xD7A3) || (c >= 0xF900 && c <= 0xFAFF) ||
           (c >= 0xFE30 && c <= 0xFE4F) || (c >= 0xFF00 && c <= 0xFF60) ||
           (c >= 0xFFE0 && c <= 0xFFE6) || (c >= 0x1F300 && c <= 0x1F64F) ||
           (c >= 0x1F900 && c <= 0x1F9FF) || (c >= 0x20000 && c <= 0x3FFFD);
}

// A combining mark: no column of its own.
bool combining(char32_t c) {
    return (c >= 0x0300 && c <= 0x036F) || (c >= 0x1AB0 && c <= 0x1AFF) ||
           (c >= 0x1DC0 && c <= 0x1DFF) || (c >= 0x20D0 && c <= 0x20FF) ||
           (c >= 0xFE20 && c <= 0xFE2F) || c == 0x200B || c == 0x200D;
}

// `s` padded with spaces to `width` columns.
std::string pad(const std::string& s, size_t width) {
    const size_t w = display_width(s);
    return w >= width ? s : s + std::string(width - w, ' ');
}

}  // namespace

size_t display_width(std::string_view s) {
    size_t w = 0;
    for (size_t i = 0; i < s.size();) {
        const auto b = static_cast<unsigned char>(s[i]);
        const size_t n = b < 0x80 ? 1 : rt::utf8_length(s, i);
        if (n <= 1) {
            ++w;
            ++i;
            continue;
        }
        char32_t c = b & (n == 2 ? 0x1F : n == 3 ? 0x0F : 0x07);
        for (size_t k = 1; k < n; ++k) c = (c << 6) | (static_cast<unsigned char>(s[i + k]) & 0x3F);
        w += combining(c) ? 0 : wide(c) ? 2 : 1;
        i += n;
    }
    return w;
}

std::vector<std::string> student_names(const std::vector<std::string>& paths) {
    namespace fs = std::filesystem;
    const auto unique = [](const std::vector<std::string>& v) {
        return std::set<std::string>(v.begin(), v.end()).size() == v.size();
    };
    std::vector<std::string> stems, folders, both;
    for (const std::string& p : paths) {
        const fs::path path(p);
        std::string folder = path.parent_path().filename().string();
        if (folder == "." || folder == "..") folder.clear();
        stems.push_back(path.stem().string());
        folders.push_back(folder);
        both.push_back(folder.empty() ? stems.back() : folder + "/" + stems.back());
    }
    if (unique(stems)) return stems;
    const bool have_folders = std::none_of(folders.begin(), folders.end(),
                                           [](const std::string& f) { return f.empty(); });
    if (have_folders && unique(folders)) return folders;
    return both;
}

std::string rule_text(const Limits& limits) {
    std::string s =
        "a pixel is off when a channel differs by more than " + num(limits.tolerance) + " of 255";
    if (limits.neighbourhood)
        s += " (on an edge of the reference, from a neighbour whose one-pixel move fits the "
             "image's 3x3 block)";
    s += "; an image passes with at most " + num(100.0 * limits.max_bad) + "% of its pixels off";
    s += limits.lossy ? "; every image under the lossy rule (3x3 means)"
                      : "; JPEG files under the lossy rule (3x3 means)";
    if (limits.width > 0)
        s += "; every image " + std::to_string(limits.width) + "x" + std::to_string(limits.height);
    else if (limits.width == 0)
        s += "; every image the first's size";
    return s;
}

std::string summary_text(const std::vector<Row>& rows) {
    size_t pass = 0, fail = 0, unreadable = 0;
    for (const Row& r : rows) (r.pass ? pass : r.unreadable ? unreadable : fail) += 1;
    return std::to_string(rows.size()) + (rows.size() == 1 ? " image: " : " images: ") +
           std::to_string(pass) + " pass, " + std::to_string(fail) + " fail, " +
           std::to_string(unreadable) + " cannot be read";
}

std::string inspect_command(const std::string& scene, const Row& r) {
    if (!r.error.empty() || r.width <= 0) return "";
    return "raytrace " + shell_word(escaped(scene)) + " --width " + std::to_string(r.width) +
           " --height " + std::to_string(r.height) + " --inspect " + std::to_string(r.c.max_x) +
           "," + std::to_string(r.c.max_y);
}

std::string reason_text(const Row& r, const Limits& limits) {
    if (!r.error.empty()) return "FAIL: " + escaped(r.error);
    const std::string rule = r.lossy ? " under the lossy rule" : "";
    if (r.pass)
        return "PASS: " + num(100.0 * r.c.share_off, 3) + "% of pixels off" + rule + " (at most " +
               num(100.0 * limits.max_bad) + "%)";
    return "FAIL: " + num(100.0 * r.c.share_off, 3) + "% of pixels off by more than " +
           num(limits.tolerance) + rule + " (at most " + num(100.0 * limits.max_bad) +
           "%); the largest difference " + num(r.c.max_diff, 1) + " at (" +
           std::to_string(r.c.max_x) + "," + std::to_string(r.c.max_y) + ")";
}

std::string gradescope_json(const std::string& scene, const std::vector<Row>& rows,
                            const Limits& limits) {
    size_t pass = 0;
    std::string tests;
    for (const Row& r : rows) {
        pass += r.pass;
        std::string output = reason_text(r, limits);
        if (const std::string cmd = inspect_command(scene, r); !cmd.empty() && !r.pass)
            output += "\nthe worst pixel, explained: " + cmd;
        if (!r.diagnosis.empty()) output += "\n" + diagnosis_text(r, "\n");
        tests += std::string(tests.empty() ? "" : ",\n") +
                 "    {\"name\": " + json_string(shown_name(r)) +
                 ", \"score\": " + (r.pass ? "1" : "0") + ", \"max_score\": 1, \"status\": \"" +
                 (r.pass ? "passed" : "failed") + "\", \"output\": " + json_string(output) + "}";
    }
    return "{\n  \"score\": " + std::to_string(pass) +
           ",\n  \"max_score\": " + std::to_string(rows.size()) + ",\n  \"output\": " +
           json_string(escaped(scene) + ": " + summary_text(rows) +
                       "\nrule: " + rule_text(limits)) +
           ",\n  \"tests\": [\n" + tests + (tests.empty() ? "" : "\n") + "  ]\n}\n";
}

// As the scene's error messages show names (rt/util/text.h), without the quotes.
std::string escaped(std::string_view s) { return rt::escape(s); }

std::string image_name(size_t row) { return "image_" + std::to_string(row + 1) + ".png"; }
std::string heat_name(size_t row) { return "heat_" + std::to_string(row + 1) + ".png"; }
std::string signed_name(size_t row) { return "signed_" + std::to_string(row + 1) + ".png"; }
std::string mutant_name(size_t row) { return "mutant_" + std::to_string(row + 1) + ".png"; }
std::string reference_name(int width, int height) {
    return "reference_" + std::to_string(width) + "x" + std::to_string(height) + ".png";
}

rt::Image scale_bar() {
    rt::Image bar(256, 12);
    for (int x = 0; x < 256; ++x)
        for (int y = 0; y < 12; ++y) bar.set(x, y, rt::heat_colour(x / 255.0));
    return bar;
}

rt::Image signed_scale_bar() {
    rt::Image bar(256, 12);
    for (int x = 0; x < 256; ++x)
        for (int y = 0; y < 12; ++y) bar.set(x, y, rt::signed_colour(x / 127.5 - 1.0));
    return bar;
}

std::string table_text(const std::vector<Row>& rows, const Limits& limits) {
    std::vector<std::string> names;
    size_t w = 7;  // "student"
    for (const Row& r : rows) {
        names.push_back(shown_name(r));
        w = std::max(w, display_width(names.back()));
    }
    std::string out = summary_text(rows) + "\nrule: " + rule_text(limits) +
                      "\n(differences in 8-bit steps of 255)\n";
    char line[512];
    std::snprintf(line, sizeof line, "  %-9s  %9s  %9s  %9s  %-11s  %s\n", "size", "mean diff",
                  "off", "max diff", "at", "result");
    out += pad("student", w) + line;
    for (size_t i = 0; i < rows.size(); ++i) {
        const Row& r = rows[i];
        // The name is padded apart, by the columns it takes (not its bytes): snprintf's buffer
        // would cut a long one, and "李明" takes four columns in six bytes.
        out += pad(names[i], w);
        if (!r.error.empty()) {
            std::snprintf(line, sizeof line, "  %-9s  ", r.width > 0 ? size_text(r).c_str() : "-");
            out += line + std::string("FAIL: ") + escaped(r.error) + "\n";
        } else {
            std::string at = "(";  // (GCC 12 warns of "(" + std::string as a restrict overlap)
            at += std::to_string(r.c.max_x) + "," + std::to_string(r.c.max_y) + ")";
            std::snprintf(line, sizeof line, "  %-9s  %9.3f  %8.3f%%  %9.1f  %-11s  %s%s\n",
                          size_text(r).c_str(), r.c.mean(), 100.0 * r.c.share_off, r.c.max_diff,
                          at.c_str(), r.pass ? "PASS" : "FAIL", r.lossy ? " (lossy rule)" : "");
            out += line;
        }
        // The diagnosis's place, under its row.
        if (!r.diagnosis.empty()) out += "    " + diagnosis_text(r, "\n    ") + "\n";
    }
    return out;
}

std::string csv_text(const std::vector<Row>& rows) {
    std::string out =
        "file,student,width,height,mean_abs_diff,share_off,max_diff,max_x,max_y,result,rule,"
        "error,diagnosis\n";
    for (const Row& r : rows) {
        out += csv_field(escaped(r.path)) + "," + csv_field(escaped(r.name)) + "," +
               std::to_string(r.width) + "," + std::to_string(r.height) + ",";
        if (r.error.empty())
            out += num(r.c.mean()) + "," + num(r.c.share_off) + "," + num(r.c.max_diff) + "," +
                   std::to_string(r.c.max_x) + "," + std::to_string(r.c.max_y) + "," +
                   (r.pass ? "pass" : "fail") + "," + (r.lossy ? "lossy" : "exact") + ",," +
                   csv_field(diagnosis_text(r, "; ")) + "\n";
        else
            out += ",,,,,fail,," + csv_field(escaped(r.error)) + ",\n";
    }
    return out;
}

namespace {

// The page's style and its script: zoom on a row, copy a command, sort by a column.
constexpr const char* kPageStyle =
    "body{font-family:sans-serif;margin:1em;background:#fafafa}\n"
    "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:4px;"
    "vertical-align:top}\nth{cursor:pointer;background:#eee}\n"
    "td:last-child{max-width:22em;font-size:90%}tr.pass td:last-child b{color:#070}\n"
    "tr.fail td:last-child b{color:#b00}code.cmd{font-size:85%;word-break:break-all}\n"
    ".diagnosis{white-space:pre-line;margin-top:.4em}\n"
    "td img{max-width:200px;image-rendering:pixelated;cursor:zoom-in}"
    "img.bar{width:200px;height:10px;vertical-align:middle}\n"
    ".legend{margin:.3em 0}.summary{font-size:120%;font-weight:bold}\n"
    "figure{display:inline-block;margin:0 1em 1em 0}figure img{max-width:240px}\n"
    "#zoom{display:none;position:fixed;inset:0;background:rgba(0,0,0,.85);z-index:9;"
    "overflow:auto;cursor:zoom-out;text-align:center;padding-top:1em}\n"
    "#zoom img{image-rendering:pixelated;margin:4px;border:1px solid #666}\n"
    "#zoom p{color:#eee}\n";
constexpr const char* kPageScript =
    "const refs = {};\n"
    "document.querySelectorAll('figure img').forEach((im) => {\n"
    "  refs[im.nextElementSibling.textContent.split(', ')[1]] = im.src; });\n"
    "const zoom = document.getElementById('zoom');\n"
    "zoom.addEventListener('click', () => { zoom.style.display = 'none'; });\n"
    "document.querySelectorAll('#t td img').forEach((im) => {\n"
    "  im.addEventListener('click', () => {\n"
    "    const tr = im.closest('tr');\n"
    "    const srcs = [...tr.querySelectorAll('img')].map((i) => i.src);\n"
    "    const ref = refs[tr.children[1].textContent];\n"
    "    if (ref) srcs.splice(1, 0, ref);\n"
    "    const k = Math.max(1, Math.floor((window.innerWidth - 40) / (srcs.length * "
    "im.naturalWidth + 20)));\n"
    "    zoom.innerHTML = '<p>' + tr.children[0].textContent + ' (x' + k + '): its image' + "
    "(ref ? ', the reference' : '') + ', the difference, brighter / darker</p>';\n"
    "    srcs.forEach((s) => { const z = document.createElement('img'); z.src = s;\n"
    "      z.width = im.naturalWidth * k; zoom.appendChild(z); });\n"
    "    zoom.style.display = 'block';\n"
    "  });\n});\n"
    "document.querySelectorAll('button.copy').forEach((b) => {\n"
    "  b.addEventListener('click', () => {\n"
    "    navigator.clipboard.writeText(b.previousElementSibling.textContent);\n"
    "    b.textContent = 'copied'; });\n});\n"
    "document.querySelectorAll('#t th').forEach((th, col) => {\n"
    "  let up = false;\n"
    "  th.addEventListener('click', () => {\n"
    "    const tb = document.querySelector('#t tbody');\n"
    "    const key = (tr) => { const td = tr.children[col];\n"
    "      return td.dataset.v !== undefined ? parseFloat(td.dataset.v) : td.textContent; };\n"
    "    up = !up;\n"
    "    [...tb.rows].sort((a, b) => { const x = key(a), y = key(b);\n"
    "      return (x < y ? -1 : x > y ? 1 : 0) * (up ? 1 : -1); })\n"
    "      .forEach((tr) => tb.appendChild(tr));\n"
    "  });\n});\n";

// Row i of the page's table: the name, the size, the image, its heat map and signed view, the
// figures, and the result (with the worst pixel's --inspect command and the diagnosis).
std::string row_html(const std::string& scene, const Row& r, size_t i, const Limits& limits) {
    std::string img = "&mdash;", heat = "&mdash;", sgn = "&mdash;";
    if (r.image_written) img = "<img src=\"" + image_name(i) + "\" alt=\"image\">";
    if (r.heat_written) heat = "<img src=\"" + heat_name(i) + "\" alt=\"difference\">";
    if (r.signed_written) sgn = "<img src=\"" + signed_name(i) + "\" alt=\"brighter or darker\">";
    const bool ok = r.error.empty();
    std::string result = "<b>" + std::string(r.pass ? "PASS" : "FAIL") + "</b><br>" +
                         html_escape(reason_text(r, limits).substr(6));
    if (const std::string cmd = inspect_command(scene, r); !cmd.empty() && !r.pass)
        result += "<br>the worst pixel, explained:<br><code class=\"cmd\">" + html_escape(cmd) +
                  "</code> <button class=\"copy\">copy</button>";
    // The mistakes that best explain a failing image (--diagnose), and the first one's render.
    if (!r.pass)
        result += "<div class=\"diagnosis\">" +
                  (r.diagnosis.empty() ? std::string()
                                       : "<b>the mistakes that best explain it</b><br>" +
                                             html_escape(diagnosis_text(r, "\n"))) +
                  (r.mutant_written ? "<br><img src=\"" + mutant_name(i) +
                                          "\" alt=\"the reference with that mistake\" "
                                          "title=\"the reference with the first mistake\">"
                                    : std::string()) +
                  "</div>";
    return "<tr class=\"" + std::string(r.pass ? "pass" : "fail") + "\"><td title=\"" +
           html_escape(escaped(r.path)) + "\">" + html_escape(shown_name(r)) + "</td><td>" +
           (r.width > 0 ? size_text(r) : "") + "</td><td>" + img + "</td><td>" + heat +
           "</td><td>" + sgn + "</td><td data-v=\"" + (ok ? num(r.c.mean()) : "1e9") + "\">" +
           (ok ? num(r.c.mean(), 3) : "") + "</td><td data-v=\"" +
           (ok ? num(r.c.share_off) : "1e9") + "\">" +
           (ok ? num(100.0 * r.c.share_off, 3) + "%" : "") + "</td><td data-v=\"" +
           (ok ? num(r.c.max_diff) : "1e9") + "\">" +
           (ok ? num(r.c.max_diff, 1) + " at (" + std::to_string(r.c.max_x) + "," +
                     std::to_string(r.c.max_y) + ")"
               : "") +
           "</td><td>" + result + "</td></tr>\n";
}

}  // namespace

std::string page_html(const std::string& scene, const std::vector<Reference>& references,
                      const std::vector<Row>& rows, const Limits& limits) {
    std::string refs;
    for (const Reference& r : references) {
        refs += "<figure><img src=\"" + reference_name(r.width, r.height) +
                "\" alt=\"reference\"><figcaption>reference, " + std::to_string(r.width) + "x" +
                std::to_string(r.height) + "</figcaption></figure>\n";
    }
    const std::string scale = num(limits.heat_scale);
    std::string body;
    for (size_t i = 0; i < rows.size(); ++i) body += row_html(scene, rows[i], i, limits);
    const std::string page =
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
        "<title>raycompare: " +
        html_escape(escaped(scene)) + "</title>\n<style>\n" + std::string(kPageStyle) +
        "</style></head><body>\n<h1>" + html_escape(escaped(scene)) +
        "</h1>\n<p class=\"summary\">" + html_escape(summary_text(rows)) +
        "</p>\n<p>rule: " + html_escape(rule_text(limits)) +
        ". Differences in 8-bit steps of 255. Click an image to zoom on its row (the image, the "
        "reference, the difference and the signed view side by side); click a column's head to "
        "sort by it.</p>\n<p class=\"legend\">difference (one scale for the class): 0 <img "
        "class=\"bar\" src=\"" +
        kScaleName + "\" alt=\"difference scale\"> " + scale +
        " steps and more</p>\n<p class=\"legend\">signed view: darker, missing light &minus;" +
        scale + " <img class=\"bar\" src=\"" + kSignedScaleName + "\" alt=\"signed scale\"> +" +
        scale + " brighter, added light</p>\n" + refs +
        "<table id=\"t\"><thead><tr><th>student</th><th>size</th><th>image</th><th>difference"
        "</th><th>brighter / darker</th><th>mean diff</th><th>off</th><th>max diff</th>"
        "<th>result</th></tr></thead>\n<tbody>\n" +
        body + "</tbody></table>\n<div id=\"zoom\"></div>\n<script>\n" + kPageScript +
        "</script>\n</body></html>\n";
    return page;
}

}  // namespace raycompare
