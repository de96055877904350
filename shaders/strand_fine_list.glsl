// Strands in compute: one pixel's list of fragments in the fine pass
// (strand_fine.comp): its NEAREST nearest fragments in depth order, a strand's
// fragments in the pixel merged into one, and the order-free tail the rest are
// blended into. The twin: render::strand_raster::blend::PixelList.
#ifndef STRAND_FINE_LIST_GLSL
#define STRAND_FINE_LIST_GLSL

float k_depth[NEAREST];
uint k_strand[NEAREST];
float k_alpha[NEAREST];
vec3 k_color[NEAREST];
uint k_count = 0u;
vec3 tail_weighted = vec3(0.0);
float tail_alpha_sum = 0.0;
float tail_transparency = 1.0;
uint tail_count = 0u;
// The light every fragment met lets through, each as a layer of its own
// (blend::PixelList::transmitted): the pixel is opaque below OPAQUE_TRANSMIT.
float seen_transmit = 1.0;

// Whether (d, s) comes before (e, t): nearer, or as near with a smaller strand.
bool nearer(float d, uint s, float e, uint t) {
    return d < e || (d == e && s < t);
}

void into_tail(float alpha, vec3 color) {
    tail_weighted += color * alpha;
    tail_alpha_sum += alpha;
    tail_transparency *= 1.0 - alpha;
    tail_count += 1u;
}

// Slot i of the list and slot j swapped.
#define SWAP_SLOTS(i, j)                                                                   \
    {                                                                                      \
        float d_ = k_depth[i]; k_depth[i] = k_depth[j]; k_depth[j] = d_;                   \
        uint s_ = k_strand[i]; k_strand[i] = k_strand[j]; k_strand[j] = s_;                \
        float a_ = k_alpha[i]; k_alpha[i] = k_alpha[j]; k_alpha[j] = a_;                   \
        vec3 c_ = k_color[i]; k_color[i] = k_color[j]; k_color[j] = c_;                    \
    }

// blend::PixelList::add: every index into the list is a constant once the loops are
// unrolled, so the list stays in registers (an index known only at run time puts it
// in memory: a GPU's local memory, a CPU driver's stack).
void add_fragment(float depth, uint strand, float alpha, vec3 color) {
    seen_transmit *= 1.0 - alpha;
    // A strand already in the list: the two shares become one fragment, as near as
    // the nearer, which then moves nearer past the ones now behind it.
    bool merged = false;
    [[unroll]] for (uint i = 0u; i < NEAREST; ++i) {
        if (i < k_count && k_strand[i] == strand) {
            float total = k_alpha[i] + alpha;
            k_color[i] = (k_color[i] * k_alpha[i] + color * alpha) / total;
            k_alpha[i] = min(total, 1.0);
            k_depth[i] = min(k_depth[i], depth);
            merged = true;
        }
    }
    if (merged) {
        [[unroll]] for (int j = int(NEAREST) - 1; j >= 1; --j) {
            if (uint(j) < k_count &&
                nearer(k_depth[j], k_strand[j], k_depth[j - 1], k_strand[j - 1])) {
                SWAP_SLOTS(j, j - 1)
            }
        }
        return;
    }
    // Behind a full list: straight to the tail.
    if (k_count == NEAREST &&
        !nearer(depth, strand, k_depth[NEAREST - 1u], k_strand[NEAREST - 1u])) {
        into_tail(alpha, color);
        return;
    }
    // Carried down the sorted list: at each slot the nearer of the two stays, the
    // other goes on; what comes out of a full list's end joins the tail.
    float cd = depth;
    uint cs = strand;
    float ca = alpha;
    vec3 cc = color;
    [[unroll]] for (uint i = 0u; i < NEAREST; ++i) {
        if (i < k_count) {
            if (nearer(cd, cs, k_depth[i], k_strand[i])) {
                float d = k_depth[i];
                uint s = k_strand[i];
                float a = k_alpha[i];
                vec3 c = k_color[i];
                k_depth[i] = cd;
                k_strand[i] = cs;
                k_alpha[i] = ca;
                k_color[i] = cc;
                cd = d;
                cs = s;
                ca = a;
                cc = c;
            }
        } else if (i == k_count) {
            k_depth[i] = cd;
            k_strand[i] = cs;
            k_alpha[i] = ca;
            k_color[i] = cc;
        }
    }
    if (k_count == NEAREST) {
        into_tail(ca, cc);
    } else {
        k_count += 1u;
    }
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
    if (tail_alpha_sum > 0.0) {
        color += transmit * (1.0 - tail_transparency) * tail_weighted / tail_alpha_sum;
        transmit *= tail_transparency;
    }
    return vec4(color, transmit);
}

#endif
