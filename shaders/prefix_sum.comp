// Exclusive prefix sum of n uints in three phases over kLanes invocations, each owning a contiguous chunk of
// ceil(n / kLanes) elements (several elements per invocation, as lavapipe likes):
//   phase 0: lane_sums[l] = sum of chunk l;
//   phase 1 (one workgroup): lane_sums = exclusive scan of lane_sums; counters[total_index] = total;
//   phase 2: output[k] = lane_sums[l] + sum of input[chunk start .. k).
// Dispatch kLanes / 64 workgroups for phases 0 and 2, one for phase 1.
#version 460

layout(local_size_x = 64) in;
const uint kLanes = 1024;
const uint kPerInvocation = kLanes / 64;  // lane sums per invocation in phase 1

layout(std430, binding = 0) readonly buffer Input { uint data_in[]; };
layout(std430, binding = 1) writeonly buffer Output { uint data_out[]; };
layout(std430, binding = 2) buffer LaneSums { uint lane_sums[]; };  // kLanes entries
layout(std430, binding = 3) buffer Counters { uint counters[]; };

layout(push_constant) uniform Push {
  uint n;
  uint phase;
  uint total_index;  // where phase 1 writes the total in counters
};

shared uint partial[64];

void main() {
  uint chunk = (n + kLanes - 1) / kLanes;
  if (phase == 0) {
    uint lane = gl_GlobalInvocationID.x;
    uint begin = min(n, lane * chunk), end = min(n, begin + chunk);
    uint sum = 0;
    for (uint k = begin; k < end; ++k) sum += data_in[k];
    lane_sums[lane] = sum;
  } else if (phase == 1) {
    uint first = gl_LocalInvocationID.x * kPerInvocation;
    uint sum = 0;
    for (uint k = 0; k < kPerInvocation; ++k) sum += lane_sums[first + k];
    partial[gl_LocalInvocationID.x] = sum;
    barrier();
    if (gl_LocalInvocationID.x == 0) {
      uint running = 0;
      for (uint k = 0; k < 64; ++k) {
        uint value = partial[k];
        partial[k] = running;
        running += value;
      }
      counters[total_index] = running;
    }
    barrier();
    uint running = partial[gl_LocalInvocationID.x];
    for (uint k = 0; k < kPerInvocation; ++k) {
      uint value = lane_sums[first + k];
      lane_sums[first + k] = running;
      running += value;
    }
  } else {
    uint lane = gl_GlobalInvocationID.x;
    uint begin = min(n, lane * chunk), end = min(n, begin + chunk);
    uint running = lane_sums[lane];
    for (uint k = begin; k < end; ++k) {
      uint value = data_in[k];
      data_out[k] = running;
      running += value;
    }
  }
}
