// libsylva_oiio.so: images other than PNG through OpenImageIO (the interface
// and why it is a module: oiio_plugin.h). Built as a module of its own; it
// links OpenImageIO and nothing of sylva's.
#include "core/io/oiio_plugin.h"

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdio>
#include <exception>
#include <memory>
#include <string>

namespace {

// OpenImageIO's messages may hold several lines (one per decoder complaint);
// an error is one line: "first; second".
std::string OneLine(std::string reason) {
  while (!reason.empty() && reason.back() == '\n') reason.pop_back();
  for (size_t at = reason.find('\n'); at != std::string::npos; at = reason.find('\n', at))
    reason.replace(at, 1, "; ");
  return reason;
}

int Fail(const std::string& reason, char* error, size_t error_size) {
  if (error_size > 0) std::snprintf(error, error_size, "%s", reason.c_str());
  return 0;
}

// OpenImageIO converts pixels on a thread pool of its own; sylva reads and
// writes many small images in parallel already (TBB), where that pool only
// adds hand-offs between threads.
void UseCallingThreadOnly() {
  static const bool done = OIIO::attribute("threads", 1);
  (void)done;
}

// Opens `path` with OpenImageIO's `format` reader, straight alpha kept;
// null with the reason in `reason` if it cannot.
std::unique_ptr<OIIO::ImageInput> Open(const char* path, const char* format, std::string* reason) {
  UseCallingThreadOnly();
  auto input = OIIO::ImageInput::create(format);
  if (input == nullptr) {
    *reason = std::string("OpenImageIO has no ") + format + " reader";
    return nullptr;
  }
  // Keep alpha unassociated (straight): sylva's images never hold
  // premultiplied colour (OpenImageIO would premultiply TIFF by default).
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  OIIO::ImageSpec spec;
  if (input->open(path, spec, config)) return input;
  std::string text = input->geterror();
  const std::string global = OIIO::geterror();
  if (!global.empty()) text += (text.empty() ? "" : "\n") + global;
  *reason = OneLine(text);
  if (reason->empty()) *reason = "damaged " + std::string(format) + " file";
  *reason = "cannot read image: " + *reason;
  return nullptr;
}

SylvaOiioHeader HeaderOf(const OIIO::ImageSpec& spec) {
  SylvaOiioHeader header{spec.width, spec.height, spec.nchannels, spec.alpha_channel};
  if (header.alpha_channel < 0 && (spec.nchannels == 2 || spec.nchannels == 4)) {
    header.alpha_channel = spec.nchannels - 1;
  }
  return header;
}

int ReadHeader(const char* path, const char* format, SylvaOiioHeader* header, char* error,
               size_t error_size) try {
  std::string reason;
  const auto input = Open(path, format, &reason);
  if (input == nullptr) return Fail(reason, error, error_size);
  *header = HeaderOf(input->spec());
  return 1;
} catch (const std::exception& e) {
  return Fail(std::string("cannot read image: ") + e.what(), error, error_size);
}

int Read(const char* path, const char* format, SylvaOiioAllocate allocate, void* context,
         SylvaOiioHeader* header, char* error, size_t error_size) try {
  std::string reason;
  const auto input = Open(path, format, &reason);
  if (input == nullptr) return Fail(reason, error, error_size);
  *header = HeaderOf(input->spec());
  if (header->width <= 0 || header->height <= 0 || header->channels <= 0) {
    return Fail("image has no pixels", error, error_size);
  }
  float* pixels = allocate(context, header);
  if (pixels == nullptr) return Fail("cannot decode image: out of memory", error, error_size);
  const bool ok = input->read_image(0, 0, 0, header->channels, OIIO::TypeDesc::FLOAT, pixels);
  // Some decoders succeed on damaged data and only leave a message: libjpeg
  // fills a truncated JPEG with grey ("Premature end of JPEG file"). A photo
  // with such a message is refused too.
  reason = OneLine(input->geterror());
  input->close();
  if (!ok || !reason.empty()) {
    return Fail("cannot decode image: " + (reason.empty() ? std::string("read failed") : reason),
                error, error_size);
  }
  return 1;
} catch (const std::exception& e) {
  return Fail(std::string("cannot decode image: ") + e.what(), error, error_size);
}

int Write(const char* path, const float* pixels, int width, int height, int channels, int sample,
          char* error, size_t error_size) try {
  OIIO::TypeDesc type = OIIO::TypeDesc::UINT8;
  if (sample == kSylvaOiioUint16) type = OIIO::TypeDesc::UINT16;
  if (sample == kSylvaOiioFloat) type = OIIO::TypeDesc::FLOAT;
  UseCallingThreadOnly();
  auto output = OIIO::ImageOutput::create(path);
  if (output == nullptr) {
    return Fail("no image writer: " + OneLine(OIIO::geterror()), error, error_size);
  }
  OIIO::ImageSpec spec(width, height, channels, type);
  if (channels == 2 || channels == 4) spec.alpha_channel = channels - 1;
  // The pixels are straight alpha; without this OpenImageIO would divide the
  // colour by alpha when writing formats that store unassociated alpha.
  spec.attribute("oiio:UnassociatedAlpha", 1);
  if (!output->open(path, spec)) return Fail(OneLine(output->geterror()), error, error_size);
  const bool ok = output->write_image(OIIO::TypeDesc::FLOAT, pixels);
  const std::string reason = ok ? std::string() : OneLine(output->geterror());
  output->close();
  return ok ? 1 : Fail(reason, error, error_size);
} catch (const std::exception& e) {
  return Fail(e.what(), error, error_size);
}

constexpr SylvaOiioPlugin kPlugin{SYLVA_OIIO_PLUGIN_VERSION, ReadHeader, Read, Write};

}  // namespace

extern "C" __attribute__((visibility("default"))) const SylvaOiioPlugin* sylva_oiio_plugin(void) {
  return &kPlugin;
}
