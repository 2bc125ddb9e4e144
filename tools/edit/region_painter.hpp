#pragma once
// How the region gets into the window, beneath the UI, in one interface with
// one implementation per device kind (chosen by device type, announced in the
// window and on stderr):
//   * upload (VK_PHYSICAL_DEVICE_TYPE_CPU, i.e. lavapipe): the certified CPU
//     engine on all cores computes the labels for the window's view (cached,
//     coarse while dragging: Editor::region), colours them, and the frame
//     copies them into the swapchain image before the UI pass. On lavapipe
//     this is far faster than shading every pixel (README, Performance).
//   * gpu (any other device type): vk::RegionDrawer shades every canvas pixel
//     with the project's region shader straight into the swapchain image, in
//     the UI's render pass before the UI (no readback); pixels the shader
//     cannot certify are decided on the host and drawn from the next frames
//     on. Depth shading (Fig. 7) is drawn by the upload path.
//   The label of every pixel is the one `cmr region` gives for the same view
//   and size.
#include <memory>
#include <optional>
#include <string>

#include "tools/edit/editor.hpp"
#include "vk/context.hpp"
#include "vk/presenter.hpp"
#include "vk/region_vk.hpp"

namespace cmr::edit {

class RegionPainter {
 public:
  virtual ~RegionPainter() = default;
  /// One line for the window and the log ("region: CPU engine, 2 threads, uploaded").
  virtual std::string describe() const = 0;
  /// Records, before the render pass, what puts the current region into the
  /// frame's image, leaving the image in colour-attachment layout. The
  /// editor's viewport must have the frame's size.
  virtual vk::Result<void> record(Editor& editor, const vk::PresentFrame& frame) = 0;
  /// Inside the render pass, before the UI: draws what record() prepared.
  virtual void draw(const vk::PresentFrame& frame) { (void)frame; }
  /// A line for the end of a scripted run (empty: nothing to say).
  virtual std::string summary() const { return {}; }
};

enum class RegionPath { automatic, gpu, upload };

/// The painter for `path`: automatic is gpu on a device whose type is not
/// CPU (and that can list uncertain pixels), upload otherwise; `precision`
/// is the gpu path's shader arithmetic (empty: fp64 where available). Errors:
/// gpu asked of a device without fragmentStoresAndAtomics (or fp64 of one
/// without shaderFloat64), Vulkan failures.
vk::Result<std::unique_ptr<RegionPainter>> make_painter(vk::Context& context, vk::Presenter& presenter,
                                                        RegionPath path,
                                                        std::optional<vk::RegionPrecision> precision = std::nullopt);

}  // namespace cmr::edit
