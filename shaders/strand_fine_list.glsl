// Strands in compute: one pixel's list of fragments in the fine pass
// (strand_fine.comp): its NEAREST nearest fragments in depth order, a strand's
// fragments in the pixel merged into one, and the tail the rest are blended into
// (into_tail; the walk brings them front to back by depth bins). The twin:
// render::strand_raster::blend::PixelList.
#ifndef STRAND_FINE_LIST_GLSL
#define STRAND_FINE_LIST_GLSL

float k_depth[NEAREST];
uint k_strand[NEAREST];
float k_alpha[NEAREST];
vec3 k_color[NEAREST];
uint k_count = 0u;
vec3 tail_color = vec3(0.0);
float tail_transparency = 1.0;
uint tail_count = 0u;
// Every fragment the pixel took (the pass counts them once the walk is over).
uint fragment_count = 0u;
// The light every fragment met lets through, each as a layer of its own
// (blend::PixelList::transmitted): the pixel is opaque below OPAQUE_TRANSMIT.
float seen_transmit = 1.0;

// Whether (d, s) comes before (e, t): nearer, or as near with a smaller strand.
bool nearer(float d, uint s, float e, uint t) {
    return d < e || (d == e && s < t);
}

// Blends a fragment into the tail: in front of what it holds if it was pushed out of
// the sorted fragments (every fragment in the tail came in behind them all, and they
// only get nearer), else behind.
void into_tail(float alpha, vec3 color, bool in_front) {
    vec3 own = alpha * color;
    tail_color = in_front ? own + (1.0 - alpha) * tail_color : tail_color + tail_transparency * own;
    tail_transparency *= 1.0 - alpha;
    tail_count += 1u;
}

// blend::PixelList::add, in one pass over the list with every index a constant once
// the loops are unrolled, so the list stays in registers (an index known only at run
// time puts it in memory: a GPU's local memory, a CPU driver's stack), and with no
// work on one side of an `if` only (a CPU driver pays for both sides of every `if`).
// A strand already in the list becomes one fragment with the new share, as near as
// the nearer, and moves nearer past the fragments now behind it; a new strand is
// placed after the fragments nearer than it, and what falls off a full list's end
// joins the tail.
void add_fragment(float depth, uint strand, float alpha, vec3 color) {
    seen_transmit *= 1.0 - alpha;
    fragment_count += 1u;
    // The slot holding the same strand (NEAREST if none), and its share.
    uint same = NEAREST;
    float same_depth = depth;
    float same_alpha = 0.0;
    vec3 same_color = vec3(0.0);
    [[unroll]] for (uint i = 0u; i < NEAREST; ++i) {
        bool hit = i < k_count && k_strand[i] == strand;
        same = hit ? i : same;
        same_depth = hit ? k_depth[i] : same_depth;
        same_alpha = hit ? k_alpha[i] : same_alpha;
        same_color = hit ? k_color[i] : same_color;
    }
    // The fragment the list takes: the new one, or the two shares as one.
    float total = same_alpha + alpha;
    float g_depth = min(same_depth, depth);
    float g_alpha = min(total, 1.0);
    vec3 g_color = (same_color * same_alpha + color * alpha) / total;
    // Where it goes: after every other fragment nearer than it (a merged fragment only
    // moves nearer, so never past its own slot).
    uint at = 0u;
    [[unroll]] for (uint i = 0u; i < NEAREST; ++i) {
        at += (i < k_count && i != same && nearer(k_depth[i], k_strand[i], g_depth, strand))
            ? 1u : 0u;
    }
    // The slots from `at` to `end` move one further: up to the merged slot, which the
    // move overwrites, or to the list's end; off a full list's end, its last fragment
    // (or the new one, behind them all) joins the tail.
    bool merged = same < NEAREST;
    uint end = merged ? same : k_count;
    bool spill = !merged && k_count == NEAREST;
    bool last_out = at < NEAREST;
    float out_alpha = last_out ? k_alpha[NEAREST - 1u] : g_alpha;
    vec3 out_color = last_out ? k_color[NEAREST - 1u] : g_color;
    [[unroll]] for (int j = int(NEAREST) - 1; j >= 0; --j) {
        uint i = uint(j);
        bool moves = i > at && i <= end;
        bool takes = i == at;
        if (j > 0) {
            k_depth[i] = moves ? k_depth[i - 1u] : k_depth[i];
            k_strand[i] = moves ? k_strand[i - 1u] : k_strand[i];
            k_alpha[i] = moves ? k_alpha[i - 1u] : k_alpha[i];
            k_color[i] = moves ? k_color[i - 1u] : k_color[i];
        }
        k_depth[i] = takes ? g_depth : k_depth[i];
        k_strand[i] = takes ? strand : k_strand[i];
        k_alpha[i] = takes ? g_alpha : k_alpha[i];
        k_color[i] = takes ? g_color : k_color[i];
    }
    if (spill) {
        into_tail(out_alpha, out_color, last_out);
    }
    k_count += !merged && !spill ? 1u : 0u;
}

// The list blended front to back, the tail behind it: the colour premultiplied by
// coverage, and the light let through.
vec4 resolve_list() {
    vec3 color = vec3(0.0);
    float transmit = 1.0;
    [[unroll]] for (uint i = 0u; i < NEAREST; ++i) {
        if (i < k_count) {
            color += transmit * k_alpha[i] * k_color[i];
            transmit *= 1.0 - k_alpha[i];
        }
    }
    color += transmit * tail_color;
    transmit *= tail_transparency;
    return vec4(color, transmit);
}

#endif
