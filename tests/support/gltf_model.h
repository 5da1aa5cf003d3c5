// Test fixture: tinygltf models built in memory (tests/pipeline/test_gltf.cpp, bench_memory
// --glb): bytes appended to buffer 0 as buffer views, and accessors over them. Header-only:
// tinygltf itself is compiled into hlod_pipeline (pipeline/read_gltf_load.cpp), which every user
// of this header links.
#pragma once

#include "pipeline/tiny_gltf_config.h"

namespace hlod::test {

constexpr int kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT, kUint = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;

// Appends `bytes` to buffer 0 (4-byte aligned) as a new buffer view; returns its index.
inline int addView(tinygltf::Model& model, const void* data, size_t bytes) {
    std::vector<unsigned char>& buffer = model.buffers[0].data;
    while (buffer.size() % 4) buffer.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0, view.byteOffset = buffer.size(), view.byteLength = bytes;
    buffer.insert(buffer.end(), static_cast<const unsigned char*>(data), static_cast<const unsigned char*>(data) + bytes);
    model.bufferViews.push_back(view);
    return static_cast<int>(model.bufferViews.size()) - 1;
}

inline int addAccessor(tinygltf::Model& model, int view, int componentType, int type, size_t count, bool normalized = false) {
    tinygltf::Accessor a;
    a.bufferView = view, a.componentType = componentType, a.type = type, a.count = count, a.normalized = normalized;
    model.accessors.push_back(a);
    return static_cast<int>(model.accessors.size()) - 1;
}

// `values` as a new buffer view and an accessor of `components`-element `type` over it; returns the accessor.
template <class T>
int addData(tinygltf::Model& model, const std::vector<T>& values, int componentType, int type, int components,
            bool normalized = false) {
    const int view = addView(model, values.data(), values.size() * sizeof(T));
    return addAccessor(model, view, componentType, type, values.size() / static_cast<size_t>(components), normalized);
}

// The default scene: one node instancing mesh 0.
inline void singleNodeScene(tinygltf::Model& model) {
    model.nodes.resize(1);
    model.nodes[0].mesh = 0;
    model.scenes.resize(1);
    model.scenes[0].nodes = {0};
    model.defaultScene = 0;
}

}  // namespace hlod::test
