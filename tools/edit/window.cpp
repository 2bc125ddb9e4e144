#include "tools/edit/window.hpp"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <numeric>
#include <optional>

#include <sys/resource.h>

#include "spline/errors.hpp"
#include "spline/parallel.hpp"
#include "spline/space.hpp"
#include "spline/spline_json.hpp"
#include "draw/draw.hpp"
#include "io/output.hpp"
#include "tools/edit/designer.hpp"
#include "tools/edit/examples.hpp"
#include "tools/edit/orbit.hpp"
#include "tools/edit/region_painter.hpp"
#include "tools/edit/script.hpp"
#include "tools/edit/ui.hpp"
#include "tools/field_flags.hpp"

namespace cmr::edit {
// The window's X11 display and window for the presenter (end of this file).
void set_x11_window(GLFWwindow* window, vk::PresenterOptions& options);
}  // namespace cmr::edit

namespace cmr::edit {
namespace {

using cmr::EnvironmentError;
using Clock = std::chrono::steady_clock;

std::string& glfw_error() {
  static std::string message;
  return message;
}

/// GLFW for the process: initialised once, terminated at the end.
struct Glfw {
  Glfw() {
    glfwSetErrorCallback([](int, const char* text) { glfw_error() = text; });
    const char* x11 = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if ((x11 == nullptr || *x11 == '\0') && (wayland == nullptr || *wayland == '\0'))
      throw EnvironmentError("no display: cmr edit opens a window; set DISPLAY or run it under xvfb-run");
    if (glfwInit() != GLFW_TRUE) throw EnvironmentError("cannot open the display: " + glfw_error());
    if (glfwVulkanSupported() != GLFW_TRUE)
      throw EnvironmentError("GLFW finds no Vulkan loader for windows: " + glfw_error());
  }
  ~Glfw() { glfwTerminate(); }
  Glfw(const Glfw&) = delete;
  Glfw& operator=(const Glfw&) = delete;
};

struct WindowHandle {
  GLFWwindow* window = nullptr;
  WindowHandle(int w, int h, const std::string& title) {
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    window = glfwCreateWindow(w, h, title.c_str(), nullptr, nullptr);
    if (window == nullptr) throw EnvironmentError("cannot create a window: " + glfw_error());
  }
  ~WindowHandle() { glfwDestroyWindow(window); }
  WindowHandle(const WindowHandle&) = delete;
  WindowHandle& operator=(const WindowHandle&) = delete;
};

template <class T>
T check(vk::Result<T> r) {
  if (!r) throw EnvironmentFieldError(r.error().message);
  return r.take();
}
void check(vk::Result<void> r) {
  if (!r) throw EnvironmentFieldError(r.error().message);
}

vk::Context make_context(GLFWwindow* window, const std::string& device) {
  vk::ContextOptions o;
  o.device_name = device;
  o.require_float64 = false;
  uint32_t count = 0;
  const char** names = glfwGetRequiredInstanceExtensions(&count);
  if (names == nullptr) throw EnvironmentError("GLFW lists no Vulkan surface extensions: " + glfw_error());
  for (uint32_t i = 0; i < count; ++i) o.instance_extensions.emplace_back(names[i]);
  o.make_surface = [window](VkInstance instance) -> vk::Result<VkSurfaceKHR> {
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    const VkResult r = glfwCreateWindowSurface(instance, window, nullptr, &surface);
    if (r != VK_SUCCESS)
      return vk::Error{vk::Errc::missing_feature, r, "cannot make a Vulkan surface for the window: " + glfw_error()};
    return surface;
  };
  return check(vk::Context::create(o));
}

/// Writes the presented pixels as a PNG (cmr::write_file_atomic).
void write_png(const std::filesystem::path& path, const vk::Screenshot& shot) {
  write_file_atomic(path, draw::rgba_png(static_cast<int>(shot.width), static_cast<int>(shot.height), shot.rgba));
}

BSpline starting_spline() {
  return BSpline::bezier({{0, 0}, {1, 2}, {3, 2.5}, {4, 0.5}}, "untitled");
}

}  // namespace

/// The window, its Vulkan objects and the editor; one frame at a time.
class App {
 public:
  App(BSpline spline, std::filesystem::path path, int width, int height, const std::string& device, bool vsync,
      RegionPath region_path, std::optional<vk::RegionPrecision> precision = std::nullopt);
  std::string painter_summary() const { return painter_->summary(); }
  ~App();
  App(const App&) = delete;
  App& operator=(const App&) = delete;

  Editor& editor() { return editor_; }
  /// A space curve's orbit view (orbit.hpp): when set, it takes the input and
  /// draws the canvas; the planar editor stays idle.
  void set_orbit(std::unique_ptr<OrbitView> v) { orbit_ = std::move(v); }
  OrbitView* orbit() { return orbit_.get(); }
  bool should_close() const { return glfwWindowShouldClose(window_.window) == GLFW_TRUE; }
  void close() { glfwSetWindowShouldClose(window_.window, GLFW_TRUE); }
  const std::string& region_path() const { return region_path_; }
  std::string device_name() const { return context_->device().name; }
  /// Polls input and renders one frame; with `shot`, reads the presented
  /// image back. Returns false when the frame was skipped (zero size).
  bool frame(vk::Screenshot* shot = nullptr);
  void resize_window(int w, int h);
  int swapchain_generation() const { return presenter_->generation(); }
  const std::string& presentation() const { return presenter_->presentation(); }
  /// Pointer input, from GLFW or a script: a move always reaches the editor
  /// (drags and pans follow it); a press over a panel goes to the panel only.
  void pointer_move(double x, double y);
  void pointer_button(MouseButton button, bool down, bool shift);
  /// Scripted runs: the script's pointer is also the panels' (ImGui's) mouse,
  /// so scripts press the same buttons and drag the same handles as a user.
  void use_script_pointer() { script_pointer_.emplace(); }
  /// Where the knot ruler was drawn in the last frame.
  const KnotRulerGeometry& ruler() const { return ruler_; }
  /// The typed fields' rectangles of the last frame (UiInfo::fields).
  const std::map<std::string, std::array<float, 4>>& fields() const { return fields_; }
  /// Scripted keyboard: text for the focused widget at the next frame, and
  /// the Enter key held down or not.
  void type_text(std::string text) { pending_text_ += text; }
  void hold_enter(bool down) { enter_down_ = down; }
  /// Writes the next presented frame to `path` as a PNG (the "export PNG"
  /// button: the editor's file with .view.png).
  void export_view(std::filesystem::path path) { export_view_ = std::move(path); }
  /// Where the last frame's time went (ms): the region layers (Editor::region),
  /// the panels and overlay (build_ui and ImGui::Render), the region's colours
  /// and upload (RegionPainter::record), drawing and presenting (the rest).
  struct Phases {
    double region = 0, ui = 0, record = 0, present = 0;
    double cpu = 0;  ///< drag_frames only: the process's CPU time (every thread)
    double vertices = 0;  ///< the panels' and overlay's vertices (ImGui's draw data)
  };
  const Phases& phases() const { return phases_; }

 private:
  static App& self(GLFWwindow* w) { return *static_cast<App*>(glfwGetWindowUserPointer(w)); }
  void install_callbacks();
  void init_imgui();

  Glfw glfw_;
  WindowHandle window_;
  std::optional<vk::Context> context_;
  std::optional<vk::Presenter> presenter_;
  std::unique_ptr<RegionPainter> painter_;
  VkDescriptorPool imgui_pool_ = VK_NULL_HANDLE;
  bool imgui_ready_ = false;
  Editor editor_;
  std::unique_ptr<OrbitView> orbit_;
  std::string region_path_;
  double frame_ms_ = 0;
  std::optional<Clock::time_point> last_frame_;  ///< when the last frame began (an animated fix moves on)
  bool export_png_ = false;
  std::filesystem::path export_view_;
  KnotRulerGeometry ruler_;
  std::map<std::string, std::array<float, 4>> fields_;
  std::string pending_text_;
  bool enter_down_ = false;
  struct ScriptPointer {
    double x = -1, y = -1;
    bool down[3] = {false, false, false};
  };
  std::optional<ScriptPointer> script_pointer_;
  Phases phases_;
};

App::App(BSpline spline, std::filesystem::path path, int width, int height, const std::string& device,
         bool vsync, RegionPath region_path, std::optional<vk::RegionPrecision> precision)
    : window_(width, height, "cmr edit"), editor_(std::move(spline), std::move(path), width, height) {
  context_.emplace(make_context(window_.window, device));
  int fw = 0, fh = 0;
  glfwGetFramebufferSize(window_.window, &fw, &fh);
  vk::PresenterOptions po;
  po.vsync = vsync;
  set_x11_window(window_.window, po);  // lavapipe presents through MIT-SHM (vk/presenter.hpp)
  if (const char* p = std::getenv("CMR_EDIT_PRESENT"); p != nullptr && std::string(p) == "swapchain")
    po.allow_shm = false;  // the swapchain on every device (comparisons, tests)
  presenter_.emplace(check(vk::Presenter::create(*context_, static_cast<uint32_t>(fw), static_cast<uint32_t>(fh), po)));
  painter_ = check(make_painter(*context_, *presenter_, region_path, precision));
  region_path_ = painter_->describe();
  std::cerr << "cmr edit: " << region_path_ << "; " << presenter_->presentation() << '\n';
  editor_.resize(fw, fh);
  install_callbacks();
  init_imgui();
}

App::~App() {
  if (presenter_) presenter_->wait_idle();
  if (imgui_ready_) {
    ImGui_ImplVulkan_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
  painter_.reset();
  if (imgui_pool_ != VK_NULL_HANDLE) vkDestroyDescriptorPool(context_->device_handle(), imgui_pool_, nullptr);
}

void App::install_callbacks() {
  glfwSetWindowUserPointer(window_.window, this);
  // Installed before ImGui's, which chains to them; input the panels take is
  // not passed on to the canvas.
  glfwSetCursorPosCallback(window_.window, [](GLFWwindow* w, double x, double y) { self(w).pointer_move(x, y); });
  glfwSetMouseButtonCallback(window_.window, [](GLFWwindow* w, int button, int action, int mods) {
    const MouseButton b = button == GLFW_MOUSE_BUTTON_LEFT    ? MouseButton::left
                          : button == GLFW_MOUSE_BUTTON_RIGHT ? MouseButton::right
                                                              : MouseButton::middle;
    self(w).pointer_button(b, action == GLFW_PRESS, (mods & GLFW_MOD_SHIFT) != 0);
  });
  glfwSetScrollCallback(window_.window, [](GLFWwindow* w, double, double dy) {
    if (ImGui::GetCurrentContext() != nullptr && ImGui::GetIO().WantCaptureMouse) return;
    const bool shift =
        glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS || glfwGetKey(w, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
    try {
      if (self(w).orbit_) return self(w).orbit_->scroll(dy);
      self(w).editor_.scroll(dy, shift);
    } catch (const InputError& e) {
      self(w).editor_.message = cli::shown_message(e);
    }
  });
  glfwSetKeyCallback(window_.window, [](GLFWwindow* w, int key, int, int action, int mods) {
    if (action != GLFW_PRESS || (ImGui::GetCurrentContext() != nullptr && ImGui::GetIO().WantCaptureKeyboard)) return;
    if (key < GLFW_KEY_A || key > GLFW_KEY_Z) return;
    const std::string name(1, static_cast<char>('a' + (key - GLFW_KEY_A)));
    try {
      if (self(w).orbit_) return orbit_key(*self(w).orbit_, name, (mods & GLFW_MOD_CONTROL) != 0);
      self(w).editor_.key(name, (mods & GLFW_MOD_CONTROL) != 0);
    } catch (const InputError& e) {
      self(w).editor_.message = cli::shown_message(e);
    }
  });
}

void App::init_imgui() {
  VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 16}};
  VkDescriptorPoolCreateInfo pool{};
  pool.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
  pool.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  pool.maxSets = 16;
  pool.poolSizeCount = 1;
  pool.pPoolSizes = sizes;
  if (VkResult r = vkCreateDescriptorPool(context_->device_handle(), &pool, nullptr, &imgui_pool_); r != VK_SUCCESS)
    throw EnvironmentError("vkCreateDescriptorPool failed for the UI");
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // the same layout every start: scripts and screenshots depend on it
  ImGui::StyleColorsLight();
  ImGui_ImplGlfw_InitForVulkan(window_.window, true);
  ImGui_ImplVulkan_InitInfo info{};
  info.Instance = context_->instance();
  info.PhysicalDevice = context_->physical_device();
  info.Device = context_->device_handle();
  info.QueueFamily = context_->queue_family_index();
  info.Queue = context_->queue();
  info.DescriptorPool = imgui_pool_;
  info.MinImageCount = std::max(2u, presenter_->min_image_count());
  info.ImageCount = std::max(info.MinImageCount, presenter_->image_count());
  info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
  ImGui_ImplVulkan_Init(&info, presenter_->render_pass());
  imgui_ready_ = true;
  check(presenter_->submit_once([](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); }));
  ImGui_ImplVulkan_DestroyFontUploadObjects();
}

void App::pointer_move(double x, double y) {
  if (script_pointer_) script_pointer_->x = x, script_pointer_->y = y;
  if (orbit_) return orbit_->mouse_move(x, y);
  editor_.mouse_move(x, y);
}

void App::pointer_button(MouseButton button, bool down, bool shift) {
  if (script_pointer_) script_pointer_->down[static_cast<int>(button)] = down;
  if (down && ImGui::GetCurrentContext() != nullptr && ImGui::GetIO().WantCaptureMouse) return;
  try {
    if (orbit_) return orbit_->mouse_button(button, down);
    editor_.mouse_button(button, down, shift);
  } catch (const InputError& e) {
    editor_.message = cli::shown_message(e);
  }
}

void App::resize_window(int w, int h) {
  glfwSetWindowSize(window_.window, w, h);
  // The X server applies the size asynchronously: wait until it has.
  for (int i = 0; i < 200; ++i) {
    glfwPollEvents();
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window_.window, &fw, &fh);
    if (fw == w && fh == h) return;
    glfwWaitEventsTimeout(0.01);
  }
}

bool App::frame(vk::Screenshot* shot) {
  const auto start = Clock::now();
  if (editor_.animating())
    editor_.advance_animation(last_frame_ ? std::chrono::duration<double>(start - *last_frame_).count() : 0.0);
  last_frame_ = start;
  glfwPollEvents();
  int fw = 0, fh = 0;
  glfwGetFramebufferSize(window_.window, &fw, &fh);
  editor_.resize(fw, fh);
  if (orbit_) orbit_->resize(fw, fh);
  ImGui_ImplVulkan_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  if (script_pointer_) {  // after the backend, which reads the real pointer
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = {static_cast<float>(script_pointer_->x), static_cast<float>(script_pointer_->y)};
    for (int b = 0; b < 3; ++b) io.MouseDown[b] = script_pointer_->down[b];
    if (!pending_text_.empty()) io.AddInputCharactersUTF8(pending_text_.c_str());
    pending_text_.clear();
    if (io.KeyMap[ImGuiKey_Enter] >= 0) io.KeysDown[io.KeyMap[ImGuiKey_Enter]] = enter_down_;
  }
  ImGui::NewFrame();
  const auto ms_since = [](Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); };
  const auto region_start = Clock::now();
  if (orbit_) (void)orbit_->region();  // the orbit view's region (low resolution at once, full when done)
  else editor_.region();  // what the panels and the painter read below
  phases_.region = ms_since(region_start);
  const auto ui_start = Clock::now();
  fields_.clear();  // the fields this frame shows
  UiInfo info{region_path_, frame_ms_, &export_png_, &ruler_, &fields_};
  if (orbit_) build_orbit_ui(*orbit_, frame_ms_);
  else build_ui(editor_, info);
  ImGui::Render();
  phases_.ui = ms_since(ui_start);
  phases_.vertices = ImGui::GetDrawData()->TotalVtxCount;
  auto begun = check(presenter_->begin_frame(static_cast<uint32_t>(fw), static_cast<uint32_t>(fh)));
  if (!begun) return false;
  const vk::PresentFrame& f = *begun;
  editor_.resize(static_cast<int>(f.extent.width), static_cast<int>(f.extent.height));
  const auto record_start = Clock::now();
  if (!orbit_) {
    check(painter_->record(editor_, f));
  } else {  // the orbit view: a white canvas (cleared, not drawn: lavapipe rasterises every pixel drawn)
    presenter_->to_transfer_dst(f);
    const VkClearColorValue white{{1.0f, 1.0f, 1.0f, 1.0f}};
    const VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(f.cmd, f.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &white, 1, &all);
    presenter_->to_attachment(f, true);
  }
  phases_.record = ms_since(record_start);
  presenter_->begin_pass(f);
  if (!orbit_) painter_->draw(f);
  ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), f.cmd);
  if (export_png_) {
    export_view_ = editor_.path();
    export_view_.replace_extension(".view.png");
    export_png_ = false;
  }
  vk::Screenshot own;
  const bool exporting = !export_view_.empty() && shot == nullptr;
  check(presenter_->end_frame(f, exporting ? &own : shot));
  if (!export_view_.empty()) {
    try {
      write_png(export_view_, exporting ? own : *shot);
      editor_.message = "view written to " + export_view_.string();
    } catch (const InputError& e) {
      editor_.message = cli::shown_message(e);
    }
    export_view_.clear();
  }
  frame_ms_ = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  phases_.present = frame_ms_ - phases_.region - phases_.ui - phases_.record;
  return true;
}

namespace {

/// Feeds a script to the app, one frame per mouse move and drag step.
class ScriptRunner {
 public:
  ScriptRunner(App& app, std::vector<ScriptCommand> commands) : app_(app), commands_(std::move(commands)) {}
  /// Runs commands up to the next one that needs a frame; false when done.
  bool step();

 private:
  void run(const ScriptCommand& c);
  /// The orbit view's commands (a space curve); false for the generic ones
  /// (mouse, press, release, wait, screenshot, resize, export-view, quit).
  bool orbit_action(const ScriptCommand& c);
  bool ui_action(const ScriptCommand& c);
  bool knot_action(const ScriptCommand& c);
  /// drag-knot I U [STEPS]: the pointer presses knot I's handle on the ruler,
  /// moves to U's place in STEPS frames and releases, a frame apart each, as
  /// a user's hand would (run as generated mouse/press/release commands).
  void drag_knot(const ScriptCommand& c);
  /// type x|y|w TEXT: the pointer clicks into the panel's field, types TEXT
  /// and presses Enter, a frame apart each, as a user does.
  void type_into(const ScriptCommand& c);
  App& app_;
  std::vector<ScriptCommand> commands_;
  std::size_t next_ = 0;
  int wait_ = 0;
  struct Drag {
    Vec2 from, to;
    int steps = 0, done = 0;
  };
  std::optional<Drag> drag_;
  bool frame_needed_ = false;
};

MouseButton button_arg(const ScriptCommand& c) {
  const std::string& b = c.args.at(0);
  if (b == "left") return MouseButton::left;
  if (b == "right") return MouseButton::right;
  if (b == "middle") return MouseButton::middle;
  throw InputError("script line " + std::to_string(c.line) + ": expected left, right or middle, got '" + b + "'");
}

bool ScriptRunner::step() {
  if (app_.editor().animating()) {  // a fix or snap moves on over its frames first
    app_.frame();
    return true;
  }
  if (wait_ > 0) {
    --wait_;
    app_.frame();
    return true;
  }
  if (drag_) {
    Drag& d = *drag_;
    ++d.done;
    const Vec2 p = d.from + (d.to - d.from) * (static_cast<double>(d.done) / d.steps);
    app_.pointer_move(p.x, p.y);
    if (d.done == d.steps) {
      app_.pointer_button(MouseButton::left, false, false);
      drag_.reset();
    }
    app_.frame();
    return true;
  }
  frame_needed_ = false;
  Editor& e = app_.editor();
  while (next_ < commands_.size() && !frame_needed_ && wait_ == 0 && !drag_ && !e.animating())
    run(commands_[next_++]);
  if (frame_needed_ || wait_ > 0 || drag_ || e.animating()) {
    app_.frame();
    return true;
  }
  return next_ < commands_.size();
}

void ScriptRunner::run(const ScriptCommand& c) {
  if (app_.orbit() != nullptr && orbit_action(c)) return;
  Editor& e = app_.editor();
  const std::string& n = c.name;
  if (n == "mouse") {
    app_.pointer_move(number_arg(c, 0), number_arg(c, 1));
    frame_needed_ = true;
  } else if (n == "press") {
    app_.pointer_button(button_arg(c), true, c.args.size() > 1 && c.args[1] == "shift");
  } else if (n == "release") {
    app_.pointer_button(button_arg(c), false, false);
  } else if (n == "drag-knot") {  // a frame first, so the ruler shows the current knots
    ScriptCommand now = c;
    now.name = "drag-knot!";  // internal: no script can spell it (parse_script rejects it)
    commands_.insert(commands_.begin() + static_cast<std::ptrdiff_t>(next_), now);
    frame_needed_ = true;
  } else if (n == "drag-knot!") {
    drag_knot(c);
  } else if (n == "type") {  // a frame first, so the panel shows the fields
    ScriptCommand now = c;
    now.name = "type!";
    commands_.insert(commands_.begin() + static_cast<std::ptrdiff_t>(next_), now);
    frame_needed_ = true;
  } else if (n == "type!") {
    type_into(c);
  } else if (n == "text!") {
    app_.type_text(c.args[0]);
    frame_needed_ = true;
  } else if (n == "enter!") {
    app_.hold_enter(c.args[0] == "down");
    frame_needed_ = true;
  } else if (n == "resize") {
    const int w = int_arg(c, 0), h = int_arg(c, 1);
    if (w < 64 || h < 64 || w > kMaxImageSize || h > kMaxImageSize)
      throw InputError("script line " + std::to_string(c.line) + ": resize: width and height must lie in 64.." +
                       std::to_string(kMaxImageSize));
    app_.resize_window(w, h);
    frame_needed_ = true;
  } else if (n == "export-view") {
    check_output_path(c.args[0], "export-view");
    app_.export_view(c.args[0]);
    frame_needed_ = true;
  } else if (n == "scroll") {
    e.scroll(number_arg(c, 0), c.args.size() > 1 && c.args[1] == "shift");
  } else if (n == "key") {
    e.key(c.args[0], c.args.size() > 1 && c.args[1] == "ctrl");
    if (c.args[0] == "x" || c.args[0] == "s")  // fix, snap: their status line, as the commands
      std::cerr << "cmr edit: script line " << c.line << ": " << e.message << '\n';
  } else if (n == "drag") {
    const int k = int_arg(c, 0);
    if (k < 0 || k >= e.doc().spline.point_count())
      throw InputError("script line " + std::to_string(c.line) + ": no point " + std::to_string(k));
    const Vec2 from = e.viewport().to_screen(e.doc().spline.points()[k]);
    const Vec2 to = e.viewport().to_screen({number_arg(c, 1), number_arg(c, 2)});
    const int steps = c.args.size() > 3 ? std::max(1, int_arg(c, 3)) : 10;
    app_.pointer_move(from.x, from.y);
    app_.pointer_button(MouseButton::left, true, false);
    if (e.dragging() != k)
      throw InputError("script line " + std::to_string(c.line) + ": point " + std::to_string(k) +
                       " is not under the cursor (off screen or covered by another point)");
    drag_ = Drag{from, to, steps, 0};
  } else if (n == "wait") {
    wait_ = std::max(0, int_arg(c, 0));
  } else if (n == "screenshot") {
    if (OrbitView* o = app_.orbit()) o->settle();  // the full-resolution region
    vk::Screenshot shot;
    app_.frame(&shot);
    write_png(c.args[0], shot);
  } else if (n == "quit") {
    next_ = commands_.size();
  } else if (!ui_action(c) && !knot_action(c)) {
    throw InputError("script line " + std::to_string(c.line) + ": '" + n + "' is not handled");
  }
}

bool ScriptRunner::orbit_action(const ScriptCommand& c) {
  OrbitView& o = *app_.orbit();
  const std::string& n = c.name;
  const std::string where = "script line " + std::to_string(c.line) + ": ";
  if (n == "mouse" || n == "press" || n == "release" || n == "wait" || n == "screenshot" || n == "resize" ||
      n == "export-view" || n == "quit")
    return false;
  frame_needed_ = true;
  if (n == "orbit") o.orbit(number_arg(c, 0), number_arg(c, 1));
  else if (n == "zoom") o.zoom(number_arg(c, 0));
  else if (n == "pan") o.pan(number_arg(c, 0), number_arg(c, 1));
  else if (n == "plane") o.set_plane_kind(parse_orbit_plane(c.args[0]));
  else if (n == "select") o.select(int_arg(c, 0));
  else if (n == "fit") o.fit();
  else if (n == "comb") o.comb = switch_arg(c, 0);
  else if (n == "ui") o.panels = switch_arg(c, 0);
  else if (n == "scroll") o.scroll(number_arg(c, 0));
  else if (n == "undo") o.undo();
  else if (n == "redo") o.redo();
  else if (n == "key") orbit_key(o, c.args[0], c.args.size() > 1 && c.args[1] == "ctrl");
  else if (n == "fix") {
    o.fix();
    std::cerr << "cmr edit: " << where << o.message << '\n';
  } else if (n == "save") {
    o.save(c.args.empty() ? o.path() : std::filesystem::path(c.args[0]));
    std::cerr << "cmr edit: " << where << o.message << '\n';
  } else if (n == "status") {
    const Vec3 q = o.spline().points()[o.selected()];
    char buf[160];
    std::snprintf(buf, sizeof buf, "selected P%d (%.17g, %.17g, %.17g) in its %s plane; here %s; |kappa| %s",
                  o.selected(), q.x, q.y, q.z, orbit_plane_name(o.plane_kind()), to_string(o.label_here()),
                  to_string(o.analysis().curvature));
    std::cerr << "cmr edit: " << where << buf << "; " << o.message << '\n';
  } else if (n == "legend") {
    for (const std::string& line : orbit_legend(o)) std::cerr << "cmr edit: legend " << line << '\n';
  } else if (n == "drag") {  // drag K A B [STEPS]: to plane coordinates (a, b) of K's plane
    const int k = int_arg(c, 0);
    if (k < 0 || k >= o.spline().unique_point_count()) throw InputError(where + "no point " + std::to_string(k));
    if (k != o.selected()) o.select(k);
    if (!o.plane()) throw InputError(where + "P" + std::to_string(k) + " has no plane to move in: " + o.message);
    const OrbitProjection p = o.projection();
    Vec2 from, to;
    if (!p.to_screen(o.spline().points()[k], from) || !p.to_screen(o.plane_point(number_arg(c, 1), number_arg(c, 2)), to))
      throw InputError(where + "drag: the point or its target is behind the camera");
    const int steps = c.args.size() > 3 ? std::max(1, int_arg(c, 3)) : 10;
    app_.pointer_move(from.x, from.y);
    app_.pointer_button(MouseButton::left, true, false);
    if (o.dragging() != k)
      throw InputError(where + "point " + std::to_string(k) +
                       " cannot be picked there (under a panel or the legend, or covered by another point)");
    drag_ = Drag{from, to, steps, 0};
  } else {
    throw InputError(where + "'" + n + "' is not available in the orbit view of a space curve");
  }
  return true;
}

void ScriptRunner::drag_knot(const ScriptCommand& c) {
  const std::string where = "script line " + std::to_string(c.line) + ": drag-knot: ";
  const KnotRulerGeometry& r = app_.ruler();
  if (!r.shown) throw InputError(where + "the knot ruler is not shown (ui off?)");
  const int i = int_arg(c, 0);
  if (i < 0 || i >= static_cast<int>(r.handles.size()))
    throw InputError(where + "no knot " + std::to_string(i));
  const double u = number_arg(c, 1);
  const int steps = c.args.size() > 2 ? std::max(1, int_arg(c, 2)) : 10;
  const float x0 = r.handles[i][0], y = r.handles[i][1], x1 = r.x_of(u);
  const Viewport& v = app_.editor().viewport();
  if (!(x0 >= 0 && x0 < v.width && y >= 0 && y < v.height))
    throw InputError(where + "knot " + std::to_string(i) + "'s handle is outside the window (make it larger)");
  const auto command = [&](std::string name, std::vector<std::string> args) {
    return ScriptCommand{std::move(name), std::move(args), c.line};
  };
  std::vector<ScriptCommand> plan = {command("mouse", {std::to_string(x0), std::to_string(y)}),
                                     command("press", {"left"}), command("wait", {"1"})};
  for (int s = 1; s <= steps; ++s)
    plan.push_back(command("mouse", {std::to_string(x0 + (x1 - x0) * s / steps), std::to_string(y)}));
  plan.push_back(command("release", {"left"}));
  plan.push_back(command("wait", {"1"}));
  commands_.insert(commands_.begin() + static_cast<std::ptrdiff_t>(next_), plan.begin(), plan.end());
}

void ScriptRunner::type_into(const ScriptCommand& c) {
  const std::string where = "script line " + std::to_string(c.line) + ": type: ";
  const auto it = app_.fields().find(c.args[0]);
  if (it == app_.fields().end())
    throw InputError(where + "no field '" + c.args[0] + "' is shown (x, y or w, with ui on and not in kappa-curve mode)");
  const auto& r = it->second;
  const float x = 0.5f * (r[0] + r[2]), y = 0.5f * (r[1] + r[3]);
  const auto command = [&](std::string name, std::vector<std::string> args) {
    return ScriptCommand{std::move(name), std::move(args), c.line};
  };
  const std::vector<ScriptCommand> plan = {
      command("mouse", {std::to_string(x), std::to_string(y)}), command("press", {"left"}), command("wait", {"1"}),
      command("release", {"left"}), command("wait", {"1"}), command("text!", {c.args[1]}), command("wait", {"1"}),
      command("enter!", {"down"}), command("wait", {"1"}), command("enter!", {"up"}), command("wait", {"1"})};
  commands_.insert(commands_.begin() + static_cast<std::ptrdiff_t>(next_), plan.begin(), plan.end());
}

bool ScriptRunner::ui_action(const ScriptCommand& c) {
  Editor& e = app_.editor();
  const std::string& n = c.name;
  if (n == "select") e.select(int_arg(c, 0));
  else if (n == "group") {
    std::vector<int> g;
    for (std::size_t i = 0; i < c.args.size(); ++i) g.push_back(int_arg(c, i));
    e.set_group(g);
  } else if (n == "all") e.set_all_points(switch_arg(c, 0));
  else if (n == "mode") {
    if (c.args[0] != "cmr" && c.args[0] != "cmrwi")
      throw InputError("script line " + std::to_string(c.line) + ": mode is cmr or cmrwi");
    e.set_mode(c.args[0] == "cmr" ? Mode::cmr : Mode::cmrwi);
  } else if (n == "depth") e.set_depth(int_arg(c, 0));
  else if (n == "shading") e.set_depth_shading(switch_arg(c, 0));
  else if (n == "split") e.set_split(c.args[0] == "none" ? std::nullopt : std::optional<int>(int_arg(c, 0)));
  else if (n == "chain") e.set_chain(switch_arg(c, 0));
  else if (n == "segments")
    e.set_segments(c.args[0] == "all" ? std::nullopt
                                      : std::optional<SegmentRange>(parse_segment_range(c.args[0], "segments")));
  else if (n == "kcurve") {
    const std::string& w = c.args[0];
    if (w == "points") e.set_kcurve(true);
    else if (w == "modify") e.kcurve_modify();
    else if (w == "off") e.set_kcurve(false);
    else throw InputError("script line " + std::to_string(c.line) + ": kcurve takes points, modify or off");
  } else if (n == "closed") e.set_kcurve_closed(switch_arg(c, 0));
  else if (n == "comb") e.show_comb = switch_arg(c, 0);
  else if (n == "ui") {
    e.show_ui = switch_arg(c, 0);
    // A frame without (or with) the panels before the next input: ImGui
    // decides what the pointer hovers from the previous frame's windows.
    frame_needed_ = true;
  }
  else if (n == "overlay") e.show_overlay = switch_arg(c, 0);
  else if (n == "view") e.set_view({number_arg(c, 0), number_arg(c, 1), number_arg(c, 2), number_arg(c, 3)});
  else if (n == "fit") e.fit_view();
  else if (n == "contour") e.switch_curve(int_arg(c, 0));
  else if (n == "constrain") e.constrain_drag = switch_arg(c, 0);
  else if (n == "legend-dock") {
    e.legend_docked = switch_arg(c, 0);
    frame_needed_ = true;
  }
  else if (n == "comb-all") e.comb_all_curves = switch_arg(c, 0);
  else if (n == "glyph") e.open_glyph(c.args[0]);
  else if (n == "save-all") {
    e.save_all();
    std::cerr << "cmr edit: script line " << c.line << ": " << e.message << '\n';
  }
  else if (n == "fit-region") {
    e.fit_region();
    std::cerr << "cmr edit: script line " << c.line << ": " << e.message << '\n';
  } else if (n == "show-point") e.set_point_shown(int_arg(c, 0), switch_arg(c, 1));
  else if (n == "comb-size") e.comb_scale = number_arg(c, 0);
  else if (n == "graph") {
    static const char* views[] = {"kappa", "abs", "log"};
    const auto v = std::find(std::begin(views), std::end(views), c.args[0]);
    if (v == std::end(views)) throw InputError("script line " + std::to_string(c.line) + ": graph is kappa, abs or log");
    e.graph_view = static_cast<int>(v - std::begin(views));
  } else if (n == "legend") {  // what the legend shows: colour (bytes) and words per line
    const Legend l = region_legend(e);
    std::cerr << "cmr edit: legend: " << l.title << '\n';
    static const char* kinds[] = {"swatch", "gradient", "outline", "dot", "square", "diamond", "line", "text"};
    for (const LegendLine& x : l.lines) {
      const auto a = bytes_of(x.colour), b = bytes_of(x.colour_to);
      char buf[64];
      std::snprintf(buf, sizeof buf, "%d,%d,%d %d,%d,%d", a[0], a[1], a[2], b[0], b[1], b[2]);
      std::cerr << "cmr edit: legend " << kinds[static_cast<int>(x.kind)] << ' ' << buf << ' ' << x.text << '\n';
    }
  }
  else if (n == "undo") e.undo();
  else if (n == "redo") e.redo();
  else if (n == "save") {  // no path: the panel's save (a font source's glyph: back into its .glif)
    e.save(c.args.empty() ? e.path() : std::filesystem::path(c.args[0]));
    std::cerr << "cmr edit: script line " << c.line << ": " << e.message << '\n';
  }
  else if (n == "export-region") e.export_region(c.args[0]);
  else return false;
  return true;
}

bool ScriptRunner::knot_action(const ScriptCommand& c) {
  Editor& e = app_.editor();
  if (c.name == "knot") {
    e.move_knot(int_arg(c, 0), number_arg(c, 1));
    return true;
  }
  if (c.name == "weight-region") {
    e.show_weight_region = switch_arg(c, 0);
    return true;
  }
  if (c.name == "weight") {
    e.set_weight(int_arg(c, 0), number_arg(c, 1));
    if (e.message.find("clamped") != std::string::npos)
      std::cerr << "cmr edit: script line " << c.line << ": " << e.message << '\n';
    return true;
  }
  if (c.name == "status") {  // what the panel shows: the selected point and the status line
    const std::string name = e.point_name(e.doc().selected);
    std::string plain = "P";  // (built with +=: GCC 12 warns falsely on "P" + std::to_string)
    plain += std::to_string(e.doc().selected);
    const bool named = name != plain;
    std::cerr << "cmr edit: script line " << c.line << ": selected P" << e.doc().selected
              << (named ? " (" + name + ")" : std::string()) << "; " << e.message << '\n';
    return true;
  }
  if (c.name == "fix" || c.name == "snap" || c.name == "fix-grid") {
    // The status line (what moved, or why nothing could) on stderr, as in the window's panel.
    if (c.name == "fix") e.fix_curve();
    else if (c.name == "fix-grid") {
      if (!c.args.empty()) e.grid_fix_gates = c.args[0];
      e.fix_on_grid();
    }
    else e.snap_selected();
    std::cerr << "cmr edit: script line " << c.line << ": " << e.message << '\n';
    frame_needed_ = true;
    return true;
  }
  if (c.name == "insert" || c.name == "remove" || c.name == "elevate" || c.name == "clamp" || c.name == "uniform") {
    // A refusal is the editor's status line, as in the window; scripts see it on stderr.
    if (!e.knot_operation(c.name, c.args.empty() ? 0 : number_arg(c, 0), c.args.size() > 1 ? number_arg(c, 1) : 0))
      std::cerr << "cmr edit: script line " << c.line << ": " << e.message << '\n';
    return true;
  }
  return false;
}

BSpline open_spline(const std::filesystem::path& file) {
  return file.empty() ? starting_spline() : read_spline_file(file);
}

/// A spline file with [x, y, z] points (the orbit view opens it).
bool is_space_file(const std::filesystem::path& file) {
  if (file.empty()) return false;
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return std::tolower(ch); });
  return ext == ".json" && spline_file_dimension(file) == 3;
}

/// Runs a script (and the final screenshot) against the app: run_editor's loop.
int run_script(App& app, const EditOptions& o, std::vector<ScriptCommand> script) {
  app.use_script_pointer();
  ScriptRunner runner(app, std::move(script));
  app.frame();
  while (runner.step()) {
  }
  if (!o.screenshot.empty()) {
    if (OrbitView* v = app.orbit()) v->settle();
    vk::Screenshot shot;
    app.frame();  // the last change visible in both swapchain images
    app.frame(&shot);
    write_png(o.screenshot, shot);
  }
  if (const std::string s = app.painter_summary(); !s.empty() && app.orbit() == nullptr)
    std::cerr << "cmr edit: " << s << '\n';
  return kEditOk;
}

/// `cmr edit SPACE.json`: the orbit view (orbit.hpp) in the editor's window.
int run_orbit(const EditOptions& o) {
  if (!o.glyph.empty()) throw InputError("--glyph: " + o.file.string() + " is a spline file, not a font");
  if (o.region_path != RegionPath::automatic || o.precision)
    throw InputError(std::string(o.precision ? "--precision" : "--region-path") +
                     ": the orbit view of a space curve computes its region on the CPU (SpaceRegionProblem); "
                     "planar splines only");
  SpaceSpline spline = o.space ? *o.space : read_space_spline_file(o.file);
  std::vector<ScriptCommand> script;
  if (!o.script.empty()) script = read_script(o.script);
  auto view = std::make_unique<OrbitView>(spline, o.file, o.width, o.height);
  view->open_on_region_point(o.point);
  App app(spline.shadow(), o.file, o.width, o.height, o.device, o.vsync, o.region_path, o.precision);
  std::cerr << "cmr edit: " << (o.source_label.empty() ? o.file.filename().string() : o.source_label)
            << ": a space curve, in the orbit view; " << view->message << '\n';
  app.set_orbit(std::move(view));
  app.frame();  // the window's size and the panel's width
  app.orbit()->face_plane();
  if (!o.script.empty() || !o.screenshot.empty()) return run_script(app, o, std::move(script));
  while (!app.should_close()) {
    if (!app.frame()) glfwWaitEventsTimeout(0.05);
  }
  return kEditOk;
}

}  // namespace

int run_editor(const EditOptions& o) {
  if (o.width < 64 || o.height < 64 || o.width > kMaxImageSize || o.height > kMaxImageSize)
    throw InputError("--size: width and height must lie in 64.." + std::to_string(kMaxImageSize));
  if (!o.screenshot.empty()) check_output_path(o.screenshot, "--screenshot");
  if (o.space || is_space_file(o.file)) return run_orbit(o);
  OpenedSource source = o.file.empty() ? OpenedSource{} : open_source(o.file, o.glyph);
  BSpline spline = source.curves.empty() ? open_spline(o.file) : source.curves[0].spline;
  const bool several = source.curves.size() > 1 || !source.font.empty() || !source.glif.empty();
  if (several) {
    std::string names;
    for (const OpenedCurve& c : source.curves) names += (names.empty() ? "" : ", ") + c.name;
    std::cerr << "cmr edit: " << source.what << " (" << names << ")\n";
  }
  std::vector<ScriptCommand> script;
  if (!o.script.empty()) script = read_script(o.script);
  const std::filesystem::path path = o.file.empty() ? std::filesystem::path("untitled.json") : o.file;
  App app(std::move(spline), path, o.width, o.height, o.device, o.vsync, o.region_path, o.precision);
  if (several) app.editor().set_source(std::move(source));
  else app.editor().point_names = read_point_names(o.file);
  app.editor().open_on_region_point(o.point);
  {  // the first view: the curve, its comb and the opened point's region
    Editor& e = app.editor();
    const std::string opened = e.message;  // the opening's status line stays
    e.fit_view();
    e.region();
    e.message = opened;
  }
  if (!o.script.empty() || !o.screenshot.empty()) return run_script(app, o, std::move(script));
  while (!app.should_close()) {
    if (!app.frame()) glfwWaitEventsTimeout(0.05);
  }
  return kEditOk;
}

namespace {

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(colon + 2);
    }
  }
  return "unknown CPU";
}

/// The 1-minute load average (other processes compete for the cores).
std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string one;
  return in >> one ? one : "unknown";
}

/// CPU time of this process so far, every thread (the Vulkan driver's
/// rasterising threads included), in ms: less sensitive to other processes
/// on the machine than wall-clock time.
double process_cpu_ms() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  const auto ms = [](const timeval& t) { return t.tv_sec * 1e3 + t.tv_usec * 1e-3; };
  return ms(u.ru_utime) + ms(u.ru_stime);
}

struct FrameStats {
  double mean = 0, p50 = 0, p95 = 0, fps = 0;
};

FrameStats stats_of(std::vector<double> ms) {
  std::sort(ms.begin(), ms.end());
  FrameStats s;
  s.mean = std::accumulate(ms.begin(), ms.end(), 0.0) / ms.size();
  const auto at = [&](double q) { return ms[std::min(ms.size() - 1, static_cast<std::size_t>(q * ms.size()))]; };
  s.p50 = at(0.5);
  s.p95 = at(0.95);
  s.fps = 1000.0 / s.mean;
  return s;
}

/// Drags point k around a circle of the window (radius a tenth of the
/// window's height about the point's place), one position per frame.
std::vector<double> drag_frames(App& app, int k, int frames, App::Phases& mean) {
  Editor& e = app.editor();
  const Vec2 centre = e.viewport().to_screen(e.doc().spline.points()[k]);
  const double r = 0.1 * e.viewport().height;
  e.mouse_move(centre.x, centre.y);
  e.mouse_button(MouseButton::left, true, false);
  std::vector<double> ms;
  const double cpu0 = process_cpu_ms();
  for (int i = 0; i < frames; ++i) {
    const double a = 2 * M_PI * i / frames;
    e.mouse_move(centre.x + r * std::sin(a), centre.y + r * (1 - std::cos(a)) * 0.5);
    const auto t0 = Clock::now();
    app.frame();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    const App::Phases& p = app.phases();
    mean.region += p.region / frames, mean.ui += p.ui / frames, mean.record += p.record / frames;
    mean.present += p.present / frames;
    mean.vertices += p.vertices / frames;
  }
  mean.cpu = (process_cpu_ms() - cpu0) / frames;
  e.mouse_button(MouseButton::left, false, false);
  return ms;
}

/// n points on a slow wave, cubic, uniform knots (the locality benchmark's
/// curve: the same shape about its middle point n/2 whatever n, the wave's
/// phase counted from it; only a short spline's ends cut the judged spans).
BSpline wave_spline(int n) {
  std::vector<Vec2> p;
  std::vector<double> knots;
  for (int i = 0; i < n; ++i) p.push_back({0.5 * (i - n / 2), std::sin(0.3 * (i - n / 2))});
  for (int i = 0; i < n + 2; ++i) knots.push_back(i);
  return BSpline::make(3, knots, p, "wave");
}

/// Region frames of the editor (headless: Editor::region_rgba, the CPU
/// engine) for a spline of n points: the middle point selected, judged on
/// the spans it acts on, a fixed view about it; each frame first moves its
/// neighbour a little, so the selected point's region changes (its fixed
/// spans changed). `revisit` false: every frame's position is new, so the
/// region is computed (the memo's patched base, the render); true: the
/// frames revisit seven positions shown before the timing, so the editor's
/// region cache serves them (the key and the colours remain; the status
/// line's reason is remembered with the layer). Returns the frames' times in ms and appends their CPU
/// times (every thread of cmr) to `cpu_ms`; the first region (every span
/// analysed, as every frame did before RegionMemo) goes to `first_ms`.
std::vector<double> locality_frames(int n, int width, int height, int frames, bool revisit, double& first_ms,
                                    std::vector<double>& cpu_ms) {
  Editor e(wave_spline(n), "wave.json", width, height);
  const int k = n / 2, d = 3;
  e.select(k);
  e.set_segments(SegmentRange{std::max(0, k - d), std::min(n - d - 1, k)});
  const Vec2 c = e.doc().spline.points()[k];
  e.set_view({c.x - 2.0, c.y - 1.5, c.x + 2.0, c.y + 1.5});
  const auto start = Clock::now();
  (void)e.region_rgba();
  first_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  const Vec2 q = e.doc().spline.points()[k + 1];
  const auto offset = [&](int i) { return Vec2{0.0, revisit ? 0.01 * (1 + i % 7) : 0.001 * (1 + i)}; };
  if (revisit) {
    for (int i = 0; i < 7; ++i) {
      e.move_point(k + 1, q + offset(i));
      (void)e.region_rgba();
    }
  }
  std::vector<double> ms;
  for (int i = 0; i < frames; ++i) {
    e.move_point(k + 1, q + offset(i));
    const double c0 = process_cpu_ms();
    const auto t0 = Clock::now();
    (void)e.region_rgba();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    cpu_ms.push_back(process_cpu_ms() - c0);
  }
  return ms;
}

}  // namespace

/// `cmr edit --bench SPACE.json`: the orbit view's drag of point o.point in
/// its plane (the region's default plane), one pointer position per frame on
/// a circle of the window (as drag_frames), after the full region is shown.
int run_orbit_bench(const BenchOptions& o) {
  if (o.region_path != RegionPath::automatic)
    throw InputError("--region-path: the orbit view of a space curve computes its region on the CPU "
                     "(SpaceRegionProblem); planar splines only");
  SpaceSpline spline = read_space_spline_file(o.file);
  if (o.point < 0 || o.point >= spline.unique_point_count())
    throw InputError("--point: no point " + std::to_string(o.point));
  auto view = std::make_unique<OrbitView>(spline, o.file, o.width, o.height);
  view->select(o.point);
  App app(spline.shadow(), o.file, o.width, o.height, o.device, false, o.region_path);
  app.set_orbit(std::move(view));
  OrbitView& v = *app.orbit();
  for (int i = 0; i < 3; ++i) app.frame();  // warm up, and the panel's width is known
  v.fit();
  v.settle();
  app.frame();
  std::printf("cmr edit benchmark (orbit view): %s, %d frames of a drag of P%d in its %s plane, %dx%d window\n",
              o.file.filename().c_str(), o.frames, o.point, orbit_plane_name(v.plane_kind()), v.width(), v.height());
  std::printf("machine: %s, %d hardware threads, load average %s; Vulkan device: %s\n", cpu_model().c_str(),
              thread_count(0), load_average().c_str(), app.device_name().c_str());
  std::printf("%s\n", app.presentation().c_str());
  Vec2 centre;
  if (!v.projection().to_screen(v.spline().points()[o.point], centre))
    throw InputError("--point: P" + std::to_string(o.point) + " is behind the camera");
  const double r = 0.1 * v.height();
  app.pointer_move(centre.x, centre.y);
  app.pointer_button(MouseButton::left, true, false);
  if (v.dragging() != o.point) throw InputError("--point: P" + std::to_string(o.point) + " cannot be picked in the view");
  std::vector<double> ms;
  App::Phases mean;
  const double cpu0 = process_cpu_ms();
  for (int i = 0; i < o.frames; ++i) {
    const double a = 2 * M_PI * i / o.frames;
    const auto t0 = Clock::now();  // the move (analysis, samples, the label there) is part of the frame
    app.pointer_move(centre.x + r * std::sin(a), centre.y + r * (1 - std::cos(a)) * 0.5);
    app.frame();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    const App::Phases& p = app.phases();
    mean.ui += p.ui / o.frames, mean.present += p.present / o.frames, mean.vertices += p.vertices / o.frames;
  }
  mean.cpu = (process_cpu_ms() - cpu0) / o.frames;
  app.pointer_button(MouseButton::left, false, false);
  const FrameStats s = stats_of(ms);
  std::printf("%-34s mean %6.2f ms  p50 %6.2f ms  p95 %6.2f ms  %6.1f fps (p95: %.1f fps)\n",
              "the dragged point in its plane:", s.mean, s.p50, s.p95, s.fps, 1000.0 / s.p95);
  std::printf("%-34s canvas and panels %.2f ms, drawing and present %.2f ms; CPU time %.2f ms "
              "(every thread of cmr); %.0f UI vertices\n",
              "  mean per frame (no move):", mean.ui, mean.present, mean.cpu, mean.vertices);
  std::printf("load average at the end: %s\n", load_average().c_str());
  return kEditOk;
}

int run_bench(const BenchOptions& o) {
  if (is_space_file(o.file)) return run_orbit_bench(o);
  BSpline spline = o.file.empty() ? fig8_spline() : read_spline_file(o.file);
  if (o.point < 0 || o.point >= spline.point_count())
    throw InputError("--point: no point " + std::to_string(o.point));
  const std::filesystem::path file = o.file.empty() ? std::filesystem::path("fig8.json") : o.file;
  App app(std::move(spline), file, o.width, o.height, o.device, false, o.region_path);
  for (int i = 0; i < 3; ++i) app.frame();  // warm up: pipelines, first region
  std::printf("cmr edit benchmark: %s, %d frames of a scripted drag of P%d, %dx%d window\n",
              file.filename().c_str(), o.frames, o.point, app.editor().viewport().width,
              app.editor().viewport().height);
  std::printf("machine: %s, %d hardware threads, load average %s; Vulkan device: %s\n", cpu_model().c_str(),
              thread_count(0), load_average().c_str(), app.device_name().c_str());
  std::printf("%s; %s\n", app.region_path().c_str(), app.presentation().c_str());
  for (bool all : {false, true}) {
    app.editor().set_all_points(all);
    app.frame();
    App::Phases phases;
    const FrameStats s = stats_of(drag_frames(app, o.point, o.frames, phases));
    std::printf("%-34s mean %6.2f ms  p50 %6.2f ms  p95 %6.2f ms  %6.1f fps (p95: %.1f fps)\n",
                all ? "every point's region overlapped:" : "the dragged point's region:", s.mean, s.p50, s.p95,
                s.fps, 1000.0 / s.p95);
    std::printf("%-34s region %.2f ms, panels %.2f ms, colours and upload %.2f ms, drawing and present %.2f ms; "
                "CPU time %.2f ms (every thread of cmr); %.0f UI vertices\n",
                "  mean per frame:", phases.region, phases.ui, phases.record, phases.present, phases.cpu, phases.vertices);
  }
  if (o.points > 0) {
    // Locality (issue 23): a region frame of a long spline against a short
    // one's, runs interleaved (the machine's load falls on both alike).
    const int frames = 30, w = app.editor().viewport().width, h = app.editor().viewport().height;
    std::printf("locality: region frames after a neighbour's move of the middle point of an N-point cubic, "
                "%d frames x 3 rounds, interleaved; load average %s\n", frames, load_average().c_str());
    for (bool revisit : {false, true}) {
      std::vector<double> small, large, cpu_small, cpu_large;
      double first_small = 0, first_large = 0, first = 0;
      for (int round = 0; round < 3; ++round) {
        for (double x : locality_frames(6, w, h, frames, revisit, first, cpu_small)) small.push_back(x);
        first_small += first / 3;
        for (double x : locality_frames(o.points, w, h, frames, revisit, first, cpu_large)) large.push_back(x);
        first_large += first / 3;
      }
      const FrameStats a = stats_of(small), b = stats_of(large), ca = stats_of(cpu_small), cb = stats_of(cpu_large);
      const char* what = revisit ? "region remembered (revisited positions)" : "region computed (new positions)";
      std::printf("%s, %d points: mean %.2f ms  p50 %.2f ms  p95 %.2f ms\n", what, 6, a.mean, a.p50, a.p95);
      std::printf("%s, %d points: mean %.2f ms  p50 %.2f ms  p95 %.2f ms\n", what, o.points, b.mean, b.p50, b.p95);
      std::printf("%s: ratio %d-point / 6-point: mean %.2f, p50 %.2f; CPU time per frame (every thread) "
                  "%.2f / %.2f ms, ratio %.2f\n",
                  what, o.points, b.mean / a.mean, b.p50 / a.p50, cb.mean, ca.mean, cb.mean / ca.mean);
      if (!revisit)
        std::printf("the first region (every span analysed, as each frame before the memo): %d points %.1f ms, "
                    "6 points %.1f ms\n",
                    o.points, first_large, first_small);
    }
  }
  std::printf("load average at the end: %s\n", load_average().c_str());
  return kEditOk;
}

}  // namespace cmr::edit

// GLFW's X11 native access (libglfw3 is built for X11). Declared here rather
// than through <GLFW/glfw3native.h>, which needs Xrandr's headers and brings
// Xlib's macros (None, Status, Bool ...): Display* is struct _XDisplay*, and
// Window an XID (unsigned long).
extern "C" struct _XDisplay* glfwGetX11Display(void);
extern "C" unsigned long glfwGetX11Window(GLFWwindow* window);

void cmr::edit::set_x11_window(GLFWwindow* window, vk::PresenterOptions& options) {
  options.x11_display = glfwGetX11Display();
  options.x11_window = glfwGetX11Window(window);
}
