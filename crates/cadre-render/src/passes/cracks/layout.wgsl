// The crack buffers' layout, shared by the detection, the exact fill (visibility/trim/
// crack.wgsl) and the resolve; `passes::cracks`' constants of the same names (HEADER,
// ENTRY_WORDS, `CrackCounts`' order) are its Rust twin.

// Words of the state's header (the counters), then `CRACK_ENTRY_WORDS` atomics an entry.
const CRACK_HEADER: u32 = 16u;
const CRACK_ENTRY_WORDS: u32 = 8u;
// The counters: `CrackCounts`, in its order.
const CRACK_COUNT_ENTRIES: u32 = 0u;
const CRACK_COUNT_OVERFLOW: u32 = 1u;
const CRACK_COUNT_HITS: u32 = 2u;
const CRACK_COUNT_SOLVES: u32 = 3u;
const CRACK_COUNT_EXACT: u32 = 4u;
const CRACK_COUNT_FAST: u32 = 5u;
const CRACK_COUNT_GAPS: u32 = 6u;
const CRACK_COUNT_OPEN: u32 = 7u;
const CRACK_COUNT_FILL_FACES: u32 = 8u;
const CRACK_COUNT_SILHOUETTES: u32 = 9u;
// An entry's pair for a pixel flagged beside a silhouette (detect.wgsl), not between two
// faces: filled only by an exact hit, never by the fast fill, and not a crack left open.
const CRACK_PAIR_SILHOUETTE: u32 = 5u;
// An entry's words: mailbox slots (faces solved) first, then the head of its hits and its
// two least miss distances.
const CRACK_MAILBOX_SLOTS: u32 = 4u;
const CRACK_WORD_HEAD: u32 = 4u;
const CRACK_WORD_MISS: u32 = 5u;
const CRACK_WORD_MISS_NEXT: u32 = 6u;
// The crack pixels the seeded solves settled (`CrackCounts::settled`).
const CRACK_COUNT_SETTLED: u32 = 10u;
// An entry's seeds (`passes::cracks::SEED_VEC4S` vec4 an entry in the seeds buffer): for
// each of `CRACK_SEEDS`, the neighbour's texel — face id, instance + 1 (0: no seed), u and
// v bits — then what the match found — 1 + its surface record, its draw record, its local
// placement — and, in the first seed's, whether the seeded solves settled the pixel (1: the
// exact fill draws no face for it).
const CRACK_SEEDS: u32 = 2u;
const CRACK_SEED_VEC4S: u32 = 4u;
