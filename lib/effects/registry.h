// Every effect, in the order they run. Adding an effect adds its folder under lib/effects/
// (effect.cpp: the Effect, no Vulkan; recorder.cpp: its Recorder), its shaders and a preset
// section, and one name here; nothing in lib/plan, lib/run or cli names it.
#pragma once

// X(name): lib/effects/<name>/ defines `const Effect& name##_effect()` and
// `std::unique_ptr<Recorder> name##_recorder(gpu::Context&)`.
#define ISG_EFFECTS(X) X(composite) X(shadows) X(reflections) X(dof)
