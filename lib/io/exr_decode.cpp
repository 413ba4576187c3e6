#include "io/exr_decode.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfThreading.h>

#include <stdexcept>
#include <thread>

namespace isg::io {

int exr_thread_count() {
  const int n = std::max(1, int(std::thread::hardware_concurrency()));
  if (Imf::globalThreadCount() != n) Imf::setGlobalThreadCount(n);
  return n;
}

void decode_exr_planes(const std::string& file, const ExrDecodeRequest& req,
                       const std::function<void*(size_t)>& plane) {
  Imf::MultiPartInputFile in(file.c_str(), exr_thread_count());
  const Imath::Box2i window(Imath::V2i(req.x0, req.y0),
                            Imath::V2i(req.x0 + req.width - 1, req.y0 + req.height - 1));
  // Planes are grouped by part (the caller lists them part by part); each part is read once.
  for (size_t first = 0; first < req.planes.size();) {
    const int p = req.planes[first].part;
    if (p < 0 || p >= in.parts()) throw std::runtime_error("there is no part " + std::to_string(p));
    Imf::InputPart part(in, p);
    const Imf::Header& h = part.header();
    // A part covers its own data window within the request's (the union of the parts'); the
    // rest of its planes stays as the caller gave it, zeros.
    const Imath::Box2i& dw = h.dataWindow();
    if (dw.min.x < window.min.x || dw.min.y < window.min.y || dw.max.x > window.max.x || dw.max.y > window.max.y) {
      throw std::runtime_error("part " + std::to_string(p) + "'s data window lies outside the request");
    }
    Imf::FrameBuffer fb;
    size_t i = first;
    for (; i < req.planes.size() && req.planes[i].part == p; ++i) {
      const std::string& name = req.planes[i].name;
      const Imf::Channel* c = h.channels().findChannel(name);
      if (!c) throw std::runtime_error("part " + std::to_string(p) + " has no channel " + name);
      // HALF converts to FLOAT exactly; UINT stays raw so the caller converts it as OIIO does.
      const Imf::PixelType type = c->type == Imf::UINT ? Imf::UINT : Imf::FLOAT;
      fb.insert(name, Imf::Slice::Make(type, plane(i), window, 4, 4 * size_t(req.width)));
    }
    part.setFrameBuffer(fb);
    part.readPixels(dw.min.y, dw.max.y);
    first = i;
  }
}

}  // namespace isg::io
