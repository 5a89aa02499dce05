#include "aravis_camera/device/frame_pool.h"

#include <set>
#include <utility>

namespace aravis_camera {

namespace {
// Every pool buffer's memory in this process, for IsPoolMemory().
std::mutex g_registry_mutex;
std::set<const void*> g_registry;
}  // namespace

// The deleter of every published frame.
struct ReturnToPool {
  std::shared_ptr<FramePool> pool;
  FramePool::Slot* slot;
  void operator()(sensor_msgs::Image*) const { pool->Return(slot); }
};

std::shared_ptr<FramePool> FramePool::Create(ArvStream* stream, size_t n_buffers, size_t payload_bytes) {
  std::shared_ptr<FramePool> pool(new FramePool());
  pool->stream_ = stream;  // the pool owns the stream: it must outlive every buffer's memory
  std::lock_guard<std::mutex> lock(g_registry_mutex);
  for (size_t i = 0; i < n_buffers; ++i) {
    auto slot = std::make_unique<Slot>();
    slot->image.data.resize(payload_bytes);
    slot->buffer = arv_buffer_new_full(payload_bytes, slot->image.data.data(), slot.get(), nullptr);
    g_registry.insert(slot->image.data.data());
    pool->slots_.push_back(std::move(slot));
  }
  return pool;
}

FramePool::~FramePool() {
  Close();
  std::lock_guard<std::mutex> lock(g_registry_mutex);
  for (const auto& slot : slots_) g_registry.erase(slot->image.data.data());
}

void FramePool::Prime() {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& slot : slots_) arv_stream_push_buffer(stream_, slot->buffer);  // the stream owns them now
}

FramePool::Slot* FramePool::FindSlot(ArvBuffer* buffer) {
  auto* slot = static_cast<Slot*>(const_cast<void*>(arv_buffer_get_user_data(buffer)));
  for (const auto& s : slots_) {
    if (s.get() == slot) return slot;
  }
  return nullptr;
}

sensor_msgs::ImagePtr FramePool::Wrap(ArvBuffer* buffer) {
  Slot* slot = FindSlot(buffer);
  if (slot == nullptr) return nullptr;
  ++in_flight_;
  return sensor_msgs::ImagePtr(&slot->image, ReturnToPool{shared_from_this(), slot});
}

void FramePool::Return(Slot* slot) {
  --in_flight_;
  Recycle(slot->buffer);
}

void FramePool::Recycle(ArvBuffer* buffer) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (stream_ != nullptr) {
    arv_stream_push_buffer(stream_, buffer);
  } else {
    g_object_unref(buffer);  // the stream is gone; the memory stays with the slot
  }
}

void FramePool::Close() {
  ArvStream* stream = nullptr;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::swap(stream, stream_);
  }
  // Finalising the stream joins its receive thread and frees the buffers it
  // still queues; after this nothing writes into the slots.
  if (stream != nullptr) g_object_unref(stream);
}

bool FramePool::IsPoolMemory(const void* data) {
  std::lock_guard<std::mutex> lock(g_registry_mutex);
  return g_registry.count(data) > 0;
}

}  // namespace aravis_camera
