// PNG textures through Debian's libpng (the desktop build; the web page has no libpng and uses
// decode_png_jpeg_stb). libpng reports errors by longjmp to a setjmp of ours: the function that
// calls setjmp holds no object with a destructor, and everything it changes lives in a PngJob
// of its caller, so the jump skips no destructor and reads no stale local (C++ [csetjmp.syn]).
#include <png.h>

#include <csetjmp>
#include <cstring>

#include "image/decode_util.h"
#include "rt/image/decode.h"

namespace rt {

namespace {

struct PngJob {
    std::string_view data;
    size_t pos = 0;
    TextureImage* out = nullptr;
    std::string* error = nullptr;
    char message[200] = {};  // libpng's error, copied before the jump
};

void on_error(png_structp png, png_const_charp message) {
    auto* job = static_cast<PngJob*>(png_get_error_ptr(png));
    std::strncpy(job->message, message, sizeof job->message - 1);
    png_longjmp(png, 1);
}

void on_warning(png_structp, png_const_charp) {}  // a damaged ancillary chunk: it is skipped

void on_read(png_structp png, png_bytep to, size_t n) {
    auto* job = static_cast<PngJob*>(png_get_io_ptr(png));
    if (n > job->data.size() - job->pos) png_error(png, "the file ends early (truncated PNG)");
    std::memcpy(to, job->data.data() + job->pos, n);
    job->pos += n;
}

// The decoding proper, between libpng's setjmp and its errors (see the top of the file).
bool run(png_structp png, png_infop info, PngJob* job) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_set_read_fn(png, job, on_read);
    png_read_info(png, info);
    const png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    if (!decode_impl::check_size(w, h, "PNG image", job->error)) return false;
    // 8-bit RGB whatever the file holds (spec §7.3: alpha dropped, grey replicated), without
    // gamma correction (texels are taken as they are): 16-bit samples keep their high byte (as
    // stb_image, the page's decoder, and the readers before this one did), palettes
    // and small greys expanded (a transparent colour becomes alpha, then dropped).
    png_set_strip_16(png);
    png_set_palette_to_rgb(png);
    png_set_expand_gray_1_2_4_to_8(png);
    png_set_strip_alpha(png);
    png_set_gray_to_rgb(png);
    const int passes = png_set_interlace_handling(png);
    png_read_update_info(png, info);
    if (png_get_rowbytes(png, info) != size_t{w} * 3 || png_get_channels(png, info) != 3)
        png_error(png, "unexpected PNG layout after conversion to RGB");
    decode_impl::start_image(job->out, w, h);
    for (int pass = 0; pass < passes; ++pass)
        for (png_uint_32 y = 0; y < h; ++y)
            png_read_row(png, &job->out->rgb[size_t{y} * w * 3], nullptr);
    // To the IEND: a file cut after its pixels is still an error, as every other damage.
    png_read_end(png, nullptr);
    return true;
}

}  // namespace

bool decode_png(std::string_view data, TextureImage* out, std::string* error) {
    static constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    if (data.size() < 8 || std::memcmp(data.data(), kSignature, 8) != 0)
        return decode_impl::fail(error, "not a PNG file");
    PngJob job;
    job.data = data;
    job.out = out;
    job.error = error;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &job, on_error, on_warning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!info) {
        png_destroy_read_struct(&png, nullptr, nullptr);
        return decode_impl::fail(error, "cannot start libpng");
    }
    bool ok = false;
    try {
        ok = run(png, info, &job);
    } catch (...) {  // std::bad_alloc from our allocation: libpng's state is freed all the same
        png_destroy_read_struct(&png, &info, nullptr);
        throw;
    }
    png_destroy_read_struct(&png, &info, nullptr);
    if (ok) return true;
    *out = TextureImage();
    if (job.message[0] != '\0') *error = job.message;  // else check_size set it
    return false;
}

}  // namespace rt
