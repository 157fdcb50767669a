// JPEG textures through Debian's libjpeg-turbo (the desktop build; the web page has no libjpeg
// and uses decode_png_jpeg_stb). libjpeg reports errors through error_exit, which must not
// return: ours longjmps to a setjmp of ours, in a function that holds no object with a destructor
// and changes nothing but a JpegJob of its caller, so the jump skips no destructor and reads no
// stale local (C++ [csetjmp.syn]). Warnings about damaged data are errors too (as djpeg
// -strict): a truncated file would otherwise decode with its missing part grey.
#include <algorithm>
#include <csetjmp>
#include <cstddef>  // before jpeglib.h, which uses size_t and FILE
#include <cstdio>
#include <cstring>
#include <string>

// jerror.h, after jpeglib.h, declares the message codes (JWRN_* among them).
// clang-format off
#include <jpeglib.h>
#include <jerror.h>
// clang-format on

#include "image/decode_util.h"
#include "rt/image/decode.h"
#include "rt/util/limits.h"

namespace rt {

namespace {

struct JpegJob {
    jpeg_error_mgr manager;  // first: libjpeg passes a pointer to it
    jpeg_progress_mgr progress = {};
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX] = {};
    TextureImage* out = nullptr;
    std::string* error = nullptr;
};

[[noreturn]] void on_error(j_common_ptr c) {
    auto* job = reinterpret_cast<JpegJob*>(c->err);
    c->err->format_message(c, job->message);
    std::longjmp(job->jump, 1);
}

// Warnings that leave the pixels as the file means them stay warnings (and are not printed);
// every other, corrupt or missing data, is an error.
void on_message(j_common_ptr c, int level) {
    if (level != -1) return;  // trace messages
    const int code = c->err->msg_code;
    if (code == JWRN_EXTRANEOUS_DATA || code == JWRN_JFIF_MAJOR || code == JWRN_ADOBE_XFORM) return;
    on_error(c);
}

void on_progress(j_common_ptr c) {
    const auto* d = reinterpret_cast<j_decompress_ptr>(c);
    if (d->input_scan_number > kMaxJpegScans) {
        auto* job = reinterpret_cast<JpegJob*>(c->err);
        std::snprintf(job->message, sizeof job->message, "JPEG file of more than %d scans",
                      kMaxJpegScans);
        std::longjmp(job->jump, 1);
    }
}

// The decoding proper, between the setjmp and libjpeg's errors (see the top of the file).
bool run(jpeg_decompress_struct* cinfo, std::string_view data, JpegJob* job) {
    if (setjmp(job->jump)) return false;
    jpeg_create_decompress(cinfo);
    jpeg_mem_src(cinfo, reinterpret_cast<const unsigned char*>(data.data()),
                 static_cast<unsigned long>(data.size()));
    jpeg_read_header(cinfo, TRUE);
    // libjpeg's own buffers: a progressive file keeps every coefficient (2 bytes a sample, up to
    // 3 samples a pixel) for the whole image. Beyond what the image budget implies, it fails
    // (Debian's libjpeg-turbo has no backing store) instead of growing.
    cinfo->mem->max_memory_to_use = static_cast<long>(
        std::min<uint64_t>(max_image_pixels(), uint64_t{1} << 40) * 8 + (uint64_t{64} << 20));
    cinfo->progress = &job->progress;
    if (!decode_impl::check_size(cinfo->image_width, cinfo->image_height, "JPEG image", job->error))
        return false;
    if (cinfo->jpeg_color_space == JCS_CMYK || cinfo->jpeg_color_space == JCS_YCCK) {
        *job->error = "CMYK JPEG images are not supported (save it as RGB)";
        return false;
    }
    // Every 8x8 block of every component costs at least one bit of Huffman-coded data (its DC
    // difference; a baseline block two, with its end of block), so a file shorter than that
    // cannot hold the image its frame header declares, and is refused before libjpeg allocates
    // for it (a progressive or multi-scan file's coefficients: 128 bytes a block, all zeroed at
    // jpeg_start_decompress) and before the image is: a 282-byte file claiming 8192x8192 cost
    // 203 MB. An arithmetic coder can spend far less on a flat block: 1/64 of a bit
    // is assumed. The bytes left after the first scan's header bound the scans' data.
    uint64_t blocks = 0;
    for (int c = 0; c < cinfo->num_components; ++c)
        blocks +=
            uint64_t{cinfo->comp_info[c].width_in_blocks} * cinfo->comp_info[c].height_in_blocks;
    const uint64_t need = cinfo->arith_code ? (blocks + 511) / 512 : (blocks + 7) / 8;
    const uint64_t have = cinfo->src->bytes_in_buffer;
    if (have < need) {
        *job->error = "truncated JPEG image: " + std::to_string(cinfo->image_width) + "x" +
                      std::to_string(cinfo->image_height) + " pixels need at least " +
                      std::to_string(need) + " bytes of compressed data, the file has " +
                      std::to_string(have) + " after its headers";
        return false;
    }
    cinfo->out_color_space = JCS_RGB;  // grey replicated (spec §7.3)
    jpeg_start_decompress(cinfo);
    const size_t w = cinfo->output_width, h = cinfo->output_height;
    if (cinfo->output_components != 3 || w != cinfo->image_width || h != cinfo->image_height) {
        *job->error = "unexpected JPEG layout after conversion to RGB";
        return false;
    }
    // The image grows with the rows that decode (its capacity at most doubling), so a file whose
    // data ends early costs what it held (libjpeg's own buffers are a few rows for a baseline
    // file).
    TextureImage* out = job->out;
    out->width = static_cast<int>(w);
    out->height = static_cast<int>(h);
    out->rgb.clear();
    const size_t total = w * h * 3;
    while (cinfo->output_scanline < h) {
        const size_t end = (size_t{cinfo->output_scanline} + 1) * w * 3;
        if (out->rgb.capacity() < end)
            out->rgb.reserve(std::min(total, std::max(end, 2 * out->rgb.capacity())));
        out->rgb.resize(end);
        JSAMPROW row = &out->rgb[size_t{cinfo->output_scanline} * w * 3];
        jpeg_read_scanlines(cinfo, &row, 1);
    }
    jpeg_finish_decompress(cinfo);  // to the EOI: a damaged tail is an error too
    return true;
}

}  // namespace

bool decode_jpeg(std::string_view data, TextureImage* out, std::string* error) {
    if (data.size() < 3 || static_cast<uint8_t>(data[0]) != 0xFF ||
        static_cast<uint8_t>(data[1]) != 0xD8)
        return decode_impl::fail(error, "not a JPEG file");
    JpegJob job;
    job.out = out;
    job.error = error;
    jpeg_decompress_struct cinfo;
    std::memset(&cinfo, 0, sizeof cinfo);
    cinfo.err = jpeg_std_error(&job.manager);
    job.manager.error_exit = on_error;
    job.manager.emit_message = on_message;
    job.progress.progress_monitor = on_progress;
    bool ok = false;
    try {
        ok = run(&cinfo, data, &job);
    } catch (...) {  // std::bad_alloc from our allocation: libjpeg's state is freed all the same
        jpeg_destroy_decompress(&cinfo);
        throw;
    }
    jpeg_destroy_decompress(&cinfo);
    if (ok) return true;
    *out = TextureImage();
    if (job.message[0] != '\0') *error = job.message;  // else run() set it
    return false;
}

}  // namespace rt
