// The renderer shared by the pixel tests of a suite (render_fixture.h).
#include "libs/render/tests/render_fixture.h"

namespace sylva::render::render_test {

std::unique_ptr<Renderer> RenderTest::renderer_;
std::string RenderTest::unavailable_;

}  // namespace sylva::render::render_test
