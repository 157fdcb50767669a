#include "report.h"

#include <algorithm>
#include <cstdio>

#include "rt/util/text.h"

namespace raycompare {

namespace {

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

}  // namespace

// As the scene's error messages show names (rt/util/text.h), without the quotes.
std::string escaped(std::string_view s) { return rt::escape(s); }

std::string image_name(size_t row) { return "image_" + std::to_string(row + 1) + ".png"; }
std::string heat_name(size_t row) { return "heat_" + std::to_string(row + 1) + ".png"; }
std::string reference_name(int width, int height) {
    return "reference_" + std::to_string(width) + "x" + std::to_string(height) + ".png";
}

rt::Image scale_bar() {
    rt::Image bar(256, 12);
    for (int x = 0; x < 256; ++x)
        for (int y = 0; y < 12; ++y) bar.set(x, y, rt::heat_colour(x / 255.0));
    return bar;
}

std::string table_text(const std::vector<Row>& rows, const Limits& limits) {
    std::vector<std::string> names;
    size_t w = 4;
    for (const Row& r : rows) {
        names.push_back(escaped(r.path));
        w = std::max(w, names.back().size());
    }
    std::string out;
    char line[512];
    std::snprintf(line, sizeof line, "%-*s  %-9s  %9s  %9s  %9s  %-11s  %s\n", static_cast<int>(w),
                  "file", "size", "mean diff", "off", "max diff", "at", "result");
    out += line;
    for (size_t i = 0; i < rows.size(); ++i) {
        const Row& r = rows[i];
        // The name is padded apart: snprintf's buffer would cut a long one.
        out += names[i] + std::string(w - names[i].size(), ' ');
        if (!r.error.empty()) {
            std::snprintf(line, sizeof line, "  %-9s  ", r.width > 0 ? size_text(r).c_str() : "-");
            out += line + std::string("FAIL: ") + escaped(r.error) + "\n";
            continue;
        }
        std::string at = "(";  // (GCC 12 warns of "(" + std::string as a restrict overlap)
        at += std::to_string(r.c.max_x) + "," + std::to_string(r.c.max_y) + ")";
        std::snprintf(line, sizeof line, "  %-9s  %9.3f  %8.3f%%  %9.1f  %-11s  %s\n",
                      size_text(r).c_str(), r.c.mean(), 100.0 * r.c.share_off, r.c.max_diff,
                      at.c_str(), r.pass ? "PASS" : "FAIL");
        out += line;
    }
    out += "(differences in 8-bit steps of 255; off: pixels off by more than " +
           num(limits.tolerance) + " in a channel; an image passes with at most " +
           num(100.0 * limits.max_bad) + "% off" +
           (limits.neighbourhood ? "; each pixel against its 3x3 neighbourhood" : "") + ")\n";
    return out;
}

std::string csv_text(const std::vector<Row>& rows) {
    std::string out =
        "file,width,height,mean_abs_diff,share_off,max_diff,max_x,max_y,result,error\n";
    for (const Row& r : rows) {
        out += csv_field(escaped(r.path)) + "," + std::to_string(r.width) + "," +
               std::to_string(r.height) + ",";
        if (r.error.empty())
            out += num(r.c.mean()) + "," + num(r.c.share_off) + "," + num(r.c.max_diff) + "," +
                   std::to_string(r.c.max_x) + "," + std::to_string(r.c.max_y) + "," +
                   (r.pass ? "pass" : "fail") + ",\n";
        else
            out += ",,,,,fail," + csv_field(escaped(r.error)) + "\n";
    }
    return out;
}

std::string page_html(const std::string& scene, const std::vector<Reference>& references,
                      const std::vector<Row>& rows, const Limits& limits) {
    std::string refs;
    for (const Reference& r : references) {
        refs += "<figure><img src=\"" + reference_name(r.width, r.height) +
                "\" alt=\"reference\"><figcaption>reference, " + std::to_string(r.width) + "x" +
                std::to_string(r.height) + "</figcaption></figure>\n";
    }
    std::string body;
    for (size_t i = 0; i < rows.size(); ++i) {
        const Row& r = rows[i];
        std::string img = "&mdash;", heat = "&mdash;";
        if (r.image_written) img = "<img src=\"" + image_name(i) + "\" alt=\"image\">";
        if (r.heat_written)
            heat = "<img src=\"" + heat_name(i) +
                   "\" alt=\"heat map\"><br><img class=\"bar\" src=\"" + kScaleName +
                   "\" alt=\"scale\"><span class=\"scale\">0 &ndash; " + num(r.heat_scale, 0) +
                   "</span>";
        const bool ok = r.error.empty();
        body += "<tr class=\"" + std::string(r.pass ? "pass" : "fail") + "\"><td>" +
                html_escape(escaped(r.path)) + "</td><td>" + (r.width > 0 ? size_text(r) : "") +
                "</td><td>" + img + "</td><td>" + heat + "</td><td data-v=\"" +
                (ok ? num(r.c.mean()) : "1e9") + "\">" + (ok ? num(r.c.mean(), 3) : "") +
                "</td><td data-v=\"" + (ok ? num(r.c.share_off) : "1e9") + "\">" +
                (ok ? num(100.0 * r.c.share_off, 3) + "%" : "") + "</td><td data-v=\"" +
                (ok ? num(r.c.max_diff) : "1e9") + "\">" +
                (ok ? num(r.c.max_diff, 1) + " at (" + std::to_string(r.c.max_x) + "," +
                          std::to_string(r.c.max_y) + ")"
                    : "") +
                "</td><td>" +
                (r.pass ? "PASS" : "FAIL" + (ok ? "" : ": " + html_escape(escaped(r.error)))) +
                "</td></tr>\n";
    }
    const std::string page =
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
        "<title>raycompare: " +
        html_escape(escaped(scene)) +
        "</title>\n<style>\n"
        "body{font-family:sans-serif;margin:1em;background:#fafafa}\n"
        "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:4px;"
        "vertical-align:top}\nth{cursor:pointer;background:#eee}\n"
        "td:last-child{max-width:16em}tr.pass td:last-child{color:#070;font-weight:bold}\n"
        "tr.fail td:last-child{color:#b00;font-weight:bold}\n"
        "img{max-width:240px;image-rendering:pixelated}img.bar{width:160px;height:8px}\n"
        ".scale{font-size:80%;margin-left:4px}figure{display:inline-block;margin:0 1em 1em 0}\n"
        "</style></head><body>\n<h1>" +
        html_escape(escaped(scene)) + "</h1>\n<p>" + std::to_string(rows.size()) +
        " images against the reference render. Differences in "
        "8-bit steps of 255; &ldquo;off&rdquo;: the share of pixels off by more than " +
        num(limits.tolerance) + " in one channel; an image passes with at most " +
        num(100.0 * limits.max_bad) + "% off" +
        (limits.neighbourhood ? "; each pixel compared with the reference's 3x3 neighbourhood"
                              : "") +
        ". Click a column's head to sort by it.</p>\n" + refs +
        "<table id=\"t\"><thead><tr><th>file</th><th>size</th><th>image</th><th>difference"
        "</th><th>mean diff</th><th>off</th><th>max diff</th><th>result</th></tr></thead>\n"
        "<tbody>\n" +
        body +
        "</tbody></table>\n<script>\n"
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
        "  });\n});\n</script>\n</body></html>\n";
    return page;
}

}  // namespace raycompare
