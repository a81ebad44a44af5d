/* SPDX-License-Identifier: Apache-2.0 */
/* The MJCF reader of the mujoco port's rules (mjcf_scan.h): the model's
 * files within limits (MuJoCo follows <include file=...> as often as it is
 * written: fifteen files each including the next four times grew it to
 * 4 GB, then std::bad_alloc; and it reads /dev/zero until memory runs
 * out), parsed into an element tree, includes spliced in, then the joints,
 * actuators and sensors read with the <default> classes applied. Only
 * XML's structure: elements, attributes (the five named entities and
 * character references), comments, processing instructions, CDATA and a
 * DOCTYPE skipped. What MuJoCo computes when it compiles is not needed. */
#define _POSIX_C_SOURCE 200809L
#include "mjcf_scan.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "roz/error.h"
#include "roz/format.h"

/* elements nested at most this deep in one file */
#define MAX_NESTING 256
/* classes a default is looked up through at most */
#define MAX_CLASS_CHAIN 64

typedef struct {
    const char *name;
    char       *value; /* references replaced in place once the tag is read */
} attr_t;

typedef struct {
    const char *tag;
    size_t      attr0, n_attr;
    long        parent, first, last, next; /* -1: none */
} node_t;

/* the <default> class an element's attributes come from */
typedef struct {
    const char *name, *parent;
    const char *joint_type, *joint_limited, *joint_range;
    const char *act_gear, *act_limited, *act_range;
} class_t;

struct roz__mjcf_doc {
    node_t  *nodes;
    size_t   n_nodes, cap_nodes;
    attr_t  *attrs;
    size_t   n_attrs, cap_attrs;
    char   **texts; /* every file's bytes, kept: the names point into them */
    size_t   n_texts, cap_texts;
    class_t *classes;
    size_t   n_classes, cap_classes;
    size_t   bytes, includes; /* read in all */
    const char *model;        /* its path, as messages name it */
    char     dir[ROZ_MJCF_PATH_MAX]; /* the main model's folder: includes are taken from it */
};

/* actuator elements; in <default> they all set the one actuator default */
static const char *const actuator_tags[] = { "general", "motor", "position", "velocity",
                                             "intvelocity", "damper", "cylinder", "muscle",
                                             "adhesion" };

static int is_actuator(const char *tag)
{
    for (size_t i = 0; i < sizeof actuator_tags / sizeof actuator_tags[0]; i++) {
        if (strcmp(tag, actuator_tags[i]) == 0)
            return 1;
    }
    return 0;
}

/* Room for @p need items of @p size in *@p p (capacity *@p cap). */
static int grow(void *p, size_t *cap, size_t need, size_t size)
{
    void **arr = p;
    if (need <= *cap)
        return ROZ_OK;
    size_t n = *cap > 0 ? *cap * 2 : 64;
    while (n < need)
        n *= 2;
    void *q = realloc(*arr, n * size);
    if (q == NULL)
        return ROZ_ENOMEM;
    *arr = q;
    *cap = n;
    return ROZ_OK;
}

/* ---- the files ------------------------------------------------------------------- */

/* A regular file's bytes (NUL-terminated, kept in the doc), within what
 * MAX_BYTES leaves; NULL with the reason in @p err. */
static char *read_file(roz__mjcf_doc_t *d, const char *path, const char *shown, size_t *len,
                       char *err, size_t errlen)
{
    struct stat st;
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        roz_format(err, errlen, "%s: cannot be read: %s", shown, strerror(errno));
        return NULL;
    }
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        roz_format(err, errlen, "%s: not a regular file", shown);
        return NULL;
    }
    size_t left = ROZ_MJCF_MAX_BYTES - d->bytes;
    size_t want = (size_t)st.st_size < left ? (size_t)st.st_size + 1 : left + 1, got = 0;
    char *buf = grow(&d->texts, &d->cap_texts, d->n_texts + 1, sizeof *d->texts) == ROZ_OK
                    ? malloc(want + 1)
                    : NULL;
    if (buf == NULL) {
        close(fd);
        roz_format(err, errlen, "%s: no memory to read it", shown);
        return NULL;
    }
    d->texts[d->n_texts++] = buf;
    while (got < want) {
        ssize_t r = read(fd, buf + got, want - got);
        if (r < 0 && errno == EINTR)
            continue;
        if (r < 0) {
            roz_format(err, errlen, "%s: cannot be read: %s", shown, strerror(errno));
            close(fd);
            return NULL;
        }
        if (r == 0)
            break;
        got += (size_t)r;
    }
    close(fd);
    if (got > left) {
        roz_format(err, errlen, "%s: the model's XML passes %d bytes in all (the model and its "
                   "includes; this reader's limit)", shown, ROZ_MJCF_MAX_BYTES);
        return NULL;
    }
    buf[got] = '\0';
    d->bytes += got;
    *len = got;
    return buf;
}

/* ---- XML ------------------------------------------------------------------------- */

static int space(char c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

static int name_char(char c)
{
    return c != '\0' && !space(c) && c != '/' && c != '>' && c != '=' && c != '<' && c != '"' &&
           c != '\'';
}

static unsigned line_of(const char *text, size_t at)
{
    unsigned line = 1;
    for (size_t i = 0; i < at; i++)
        line += text[i] == '\n';
    return line;
}

/* An attribute value's references replaced in place; 0 on one XML has not. */
static int unescape(char *v)
{
    static const struct { const char *ref; char c; } named[] = {
        { "lt;", '<' }, { "gt;", '>' }, { "amp;", '&' }, { "quot;", '"' }, { "apos;", '\'' },
    };
    char *out = v;
    for (const char *in = v; *in != '\0';) {
        if (*in != '&') {
            *out++ = *in++;
            continue;
        }
        in++;
        int done = 0;
        for (size_t k = 0; k < sizeof named / sizeof named[0] && !done; k++) {
            size_t n = strlen(named[k].ref);
            if (strncmp(in, named[k].ref, n) == 0) {
                *out++ = named[k].c;
                in += n;
                done = 1;
            }
        }
        if (!done && in[0] == '#') {
            int hex = in[1] == 'x';
            char *end;
            long c = strtol(in + 1 + hex, &end, hex ? 16 : 10);
            if (end == in + 1 + hex || *end != ';' || c < 1 || c > 127)
                return 0; /* past ASCII: no name of a joint or a sensor has one */
            *out++ = (char)c;
            in = end + 1;
            done = 1;
        }
        if (!done)
            return 0;
    }
    *out = '\0';
    return 1;
}

static long add_node(roz__mjcf_doc_t *d, const char *tag, long parent)
{
    if (grow(&d->nodes, &d->cap_nodes, d->n_nodes + 1, sizeof *d->nodes) != ROZ_OK)
        return -1;
    long k = (long)d->n_nodes++;
    node_t *n = &d->nodes[k];
    n->tag = tag;
    n->attr0 = d->n_attrs;
    n->n_attr = 0;
    n->parent = parent;
    n->first = n->last = n->next = -1;
    if (parent >= 0) {
        node_t *p = &d->nodes[parent];
        if (p->last >= 0)
            d->nodes[p->last].next = k;
        else
            p->first = k;
        p->last = k;
    }
    return k;
}

#define NOT_XML(what)                                                                          \
    do {                                                                                       \
        roz_format(err, errlen, "%s: not XML: %s, line %u", shown, what, line_of(text, i));    \
        return -1;                                                                             \
    } while (0)

/* Skips from @p i past @p end; 0 when it is not there. */
static int skip_past(const char *text, size_t len, size_t *i, const char *end)
{
    size_t n = strlen(end);
    for (size_t k = *i; k + n <= len; k++) {
        if (memcmp(text + k, end, n) == 0) {
            *i = k + n;
            return 1;
        }
    }
    return 0;
}

/* One file's text into the tree (in place: names and values are NUL
 * terminated inside it); its root element, or -1 with @p err said. */
static long parse(roz__mjcf_doc_t *d, char *text, size_t len, const char *shown, char *err,
                  size_t errlen)
{
    long stack[MAX_NESTING];
    int top = 0;
    long root = -1;
    size_t i = 0;
    if (memchr(text, '\0', len) != NULL) {
        i = (size_t)((char *)memchr(text, '\0', len) - text);
        NOT_XML("a NUL byte");
    }
    while (i < len) {
        if (text[i] != '<') {
            if (top == 0 && !space(text[i]))
                NOT_XML(root < 0 ? "text before the root element" : "text after the root element");
            i++;
            continue;
        }
        size_t at = i;
        if (strncmp(text + i, "<?", 2) == 0) {
            if (!skip_past(text, len, &i, "?>"))
                NOT_XML("an unclosed <?");
            continue;
        }
        if (strncmp(text + i, "<!--", 4) == 0) {
            if (!skip_past(text, len, &i, "-->"))
                NOT_XML("an unclosed comment");
            continue;
        }
        if (strncmp(text + i, "<![CDATA[", 9) == 0) {
            if (!skip_past(text, len, &i, "]]>") || top == 0)
                NOT_XML("a CDATA section out of place or unclosed");
            continue;
        }
        if (strncmp(text + i, "<!", 2) == 0) {
            if (!skip_past(text, len, &i, ">") || root >= 0)
                NOT_XML("a declaration out of place or unclosed");
            continue;
        }
        if (text[i + 1] == '/') { /* an end tag: its element's */
            size_t s = i + 2, e = s;
            while (name_char(text[e]))
                e++;
            i = e;
            while (space(text[i]))
                i++;
            if (text[i] != '>' || top == 0)
                NOT_XML("a stray end tag");
            const char *open_tag = d->nodes[stack[top - 1]].tag;
            if (strlen(open_tag) != e - s || memcmp(open_tag, text + s, e - s) != 0)
                NOT_XML("mismatched tag");
            top--;
            i++;
            continue;
        }
        /* a start tag */
        size_t s = i + 1, e = s;
        while (name_char(text[e]))
            e++;
        if (e == s)
            NOT_XML("not well-formed (invalid token)");
        if (top == 0 && root >= 0)
            NOT_XML("junk after the root element");
        if (top == MAX_NESTING)
            NOT_XML("elements nested too deep for this reader");
        long k = add_node(d, text + s, top > 0 ? stack[top - 1] : -1);
        if (k < 0) {
            roz_format(err, errlen, "%s: no memory to read it", shown);
            return -1;
        }
        size_t ends[2 * 256 + 1]; /* where a NUL goes once the tag is read */
        size_t n_ends = 0;
        ends[n_ends++] = e;
        i = e;
        int closed = 0;
        for (;;) {
            while (space(text[i]))
                i++;
            if (text[i] == '>') {
                i++;
                break;
            }
            if (text[i] == '/' && text[i + 1] == '>') {
                i += 2;
                closed = 1;
                break;
            }
            size_t as = i, ae = i;
            while (name_char(text[ae]))
                ae++;
            i = ae;
            while (space(text[i]))
                i++;
            if (ae == as || text[i] != '=')
                NOT_XML("not well-formed (invalid token)");
            i++;
            while (space(text[i]))
                i++;
            char q = text[i];
            const char *close = q == '"' || q == '\'' ? memchr(text + i + 1, q, len - i - 1) : NULL;
            if (close == NULL || memchr(text + i + 1, '<', (size_t)(close - text) - i - 1) != NULL)
                NOT_XML("not well-formed (invalid token)");
            if (n_ends + 2 > sizeof ends / sizeof ends[0])
                NOT_XML("more attributes than this reader takes");
            if (grow(&d->attrs, &d->cap_attrs, d->n_attrs + 1, sizeof *d->attrs) != ROZ_OK) {
                roz_format(err, errlen, "%s: no memory to read it", shown);
                return -1;
            }
            d->attrs[d->n_attrs].name = text + as;
            d->attrs[d->n_attrs].value = text + i + 1;
            d->n_attrs++;
            d->nodes[k].n_attr++;
            ends[n_ends++] = ae;
            ends[n_ends++] = (size_t)(close - text);
            i = (size_t)(close - text) + 1;
            if (!space(text[i]) && text[i] != '>' && text[i] != '/')
                NOT_XML("not well-formed (invalid token)");
        }
        for (size_t m = 0; m < n_ends; m++)
            text[ends[m]] = '\0';
        node_t *n = &d->nodes[k];
        for (size_t a = 0; a < n->n_attr; a++) {
            if (!unescape(d->attrs[n->attr0 + a].value)) {
                i = at;
                NOT_XML("undefined entity");
            }
        }
        if (root < 0)
            root = k;
        if (!closed)
            stack[top++] = k;
    }
    if (root < 0)
        NOT_XML("no element found");
    if (top > 0)
        NOT_XML("unclosed element");
    return root;
}

#undef NOT_XML

static const char *attr(const roz__mjcf_doc_t *d, long k, const char *name)
{
    const node_t *n = &d->nodes[k];
    for (size_t a = 0; a < n->n_attr; a++) {
        if (strcmp(d->attrs[n->attr0 + a].name, name) == 0)
            return d->attrs[n->attr0 + a].value;
    }
    return NULL;
}

/* ---- includes -------------------------------------------------------------------- */

static int expand(roz__mjcf_doc_t *d, long parent, const char *label, int depth, char *err,
                  size_t errlen);

/* Include element @p k (the child after @p prev of @p parent) replaced by
 * the children of the included file's root. @p label names the file it is
 * in: NULL the model, else its <include>. Messages name the model and the
 * last two includes that lead to the problem ("...:" for any before). */
static int include(roz__mjcf_doc_t *d, long parent, long prev, long k, const char *label,
                   int depth, char *err, size_t errlen)
{
    char where[2 * ROZ_MJCF_PATH_MAX + 64], own[ROZ_MJCF_PATH_MAX + 32], path[ROZ_MJCF_PATH_MAX];
    const char *name = attr(d, k, "file");
    if (name == NULL || name[0] == '\0') {
        roz_format(err, errlen, "%s%s%s%s: an <include> without a file", d->model,
                   depth >= 2 ? ": ..." : "", label != NULL ? ": " : "", label ? label : "");
        return ROZ_EINVAL;
    }
    roz_format(own, sizeof own, "<include file=\"%s\">", name);
    roz_format(where, sizeof where, "%s%s%s%s: %s", d->model, depth >= 2 ? ": ..." : "",
               label != NULL ? ": " : "", label != NULL ? label : "", own);
    if (depth >= ROZ_MJCF_MAX_DEPTH) {
        roz_format(err, errlen, "%s: includes nested more than %d deep", where,
                   ROZ_MJCF_MAX_DEPTH);
        return ROZ_EINVAL;
    }
    if (++d->includes > ROZ_MJCF_MAX_INCLUDES) {
        roz_format(err, errlen, "%s: more than %d includes in all (this reader's limit)", where,
                   ROZ_MJCF_MAX_INCLUDES);
        return ROZ_EINVAL;
    }
    if ((size_t)roz_format(path, sizeof path, "%s%s", name[0] == '/' ? "" : d->dir, name) >=
        sizeof path) {
        roz_format(err, errlen, "%s: the path is longer than %d bytes", where,
                   ROZ_MJCF_PATH_MAX - 1);
        return ROZ_EINVAL;
    }
    size_t len;
    char *text = read_file(d, path, where, &len, err, errlen);
    long sub = text != NULL ? parse(d, text, len, where, err, errlen) : -1;
    if (sub < 0 || expand(d, sub, own, depth + 1, err, errlen) != ROZ_OK)
        return ROZ_EINVAL;
    /* splice: prev -> sub's children -> k's next */
    node_t *p = &d->nodes[parent];
    long next = d->nodes[k].next, first = d->nodes[sub].first, last = d->nodes[sub].last;
    for (long c = first; c >= 0; c = d->nodes[c].next)
        d->nodes[c].parent = parent;
    if (first < 0) {
        first = next;
    } else {
        d->nodes[last].next = next;
    }
    if (prev >= 0)
        d->nodes[prev].next = first;
    else
        p->first = first;
    if (next < 0)
        p->last = last >= 0 ? last : prev;
    return ROZ_OK;
}

/* Every <include> below @p parent replaced, in document order. */
static int expand(roz__mjcf_doc_t *d, long parent, const char *label, int depth, char *err,
                  size_t errlen)
{
    long prev = -1;
    for (long c = d->nodes[parent].first; c >= 0;) {
        long next = d->nodes[c].next;
        if (strcmp(d->nodes[c].tag, "include") == 0) {
            long after = prev; /* the last node spliced in is the next one's prev */
            if (include(d, parent, prev, c, label, depth, err, errlen) != ROZ_OK)
                return ROZ_EINVAL;
            for (long x = after >= 0 ? d->nodes[after].next : d->nodes[parent].first;
                 x >= 0 && x != next; x = d->nodes[x].next)
                prev = x;
        } else {
            if (expand(d, c, label, depth, err, errlen) != ROZ_OK)
                return ROZ_EINVAL;
            prev = c;
        }
        c = next;
    }
    return ROZ_OK;
}

/* ---- defaults -------------------------------------------------------------------- */

static void add_class(roz__mjcf_doc_t *d, long node, const char *parent, int *nomem)
{
    const char *name = attr(d, node, "class");
    if (name == NULL && parent != NULL)
        return; /* a nested default names its class */
    if (grow(&d->classes, &d->cap_classes, d->n_classes + 1, sizeof *d->classes) != ROZ_OK) {
        *nomem = 1;
        return;
    }
    class_t *c = &d->classes[d->n_classes++];
    memset(c, 0, sizeof *c);
    c->name = name != NULL ? name : "main";
    c->parent = parent;
    for (long k = d->nodes[node].first; k >= 0; k = d->nodes[k].next) {
        const char *tag = d->nodes[k].tag, *v;
        if (strcmp(tag, "joint") == 0) {
            if ((v = attr(d, k, "type")) != NULL)
                c->joint_type = v;
            if ((v = attr(d, k, "actuatorfrclimited")) != NULL)
                c->joint_limited = v;
            if ((v = attr(d, k, "actuatorfrcrange")) != NULL)
                c->joint_range = v;
        } else if (is_actuator(tag)) {
            if ((v = attr(d, k, "gear")) != NULL)
                c->act_gear = v;
            if ((v = attr(d, k, "forcelimited")) != NULL)
                c->act_limited = v;
            if ((v = attr(d, k, "forcerange")) != NULL)
                c->act_range = v;
        }
    }
    const char *self = c->name;
    for (long k = d->nodes[node].first; k >= 0; k = d->nodes[k].next) {
        if (strcmp(d->nodes[k].tag, "default") == 0)
            add_class(d, k, self, nomem);
    }
}

/* The class @p name's value of the field at @p offset, else its parents' (the
 * last class of a name is the one that counts). */
static const char *class_value(const roz__mjcf_doc_t *d, const char *name, size_t offset)
{
    for (int seen = 0; name != NULL && seen < MAX_CLASS_CHAIN; seen++) {
        const class_t *c = NULL;
        for (size_t i = d->n_classes; i-- > 0 && c == NULL;) {
            if (strcmp(d->classes[i].name, name) == 0)
                c = &d->classes[i];
        }
        if (c == NULL)
            return NULL;
        const char *v = *(const char *const *)((const char *)c + offset);
        if (v != NULL)
            return v;
        name = c->parent;
    }
    return NULL;
}

/* An element's own attribute, else its class's (its class attribute, else @p cls). */
static const char *value(const roz__mjcf_doc_t *d, long k, const char *cls, const char *name,
                         size_t offset)
{
    const char *v = attr(d, k, name);
    if (v != NULL)
        return v;
    const char *own = attr(d, k, "class");
    return class_value(d, own != NULL ? own : cls, offset);
}

/* The numbers of a whitespace-separated list: how many (at most @p cap
 * kept), or -1 when one is not a number. */
static int floats(const char *text, double *out, int cap)
{
    int n = 0;
    if (text == NULL)
        return -1;
    for (const char *p = text;;) {
        while (space(*p))
            p++;
        if (*p == '\0')
            return n;
        char *end;
        double x = strtod(p, &end);
        if (end == p || (*end != '\0' && !space(*end)))
            return -1;
        if (n < cap)
            out[n] = x;
        n++;
        p = end;
    }
}

/* MuJoCo's *limited = "auto" (the default): limited when a range is given. */
static int limited(const char *flag, const char *range, double out[2])
{
    double r[2];
    if (flag != NULL && strcmp(flag, "false") == 0)
        return 0;
    if (floats(range, r, 2) != 2)
        return 0;
    out[0] = r[0];
    out[1] = r[1];
    return 1;
}

/* ---- the model ------------------------------------------------------------------- */

#define FIELD(f) offsetof(class_t, f)

typedef struct {
    roz__mjcf_model_t *m;
    size_t             cap_joints, cap_actuators, cap_sensors;
} build_t;

static const char *joint_type(const char *t)
{
    return t == NULL ? "hinge" : t;
}

static int add_joint(const roz__mjcf_doc_t *d, build_t *b, long k, const char *cls, int free)
{
    const char *name = attr(d, k, "name");
    if (name == NULL || (free && name[0] == '\0'))
        return ROZ_OK;
    for (size_t i = 0; i < b->m->n_joints; i++) {
        if (strcmp(b->m->joints[i].name, name) == 0)
            return ROZ_OK; /* the first of a name */
    }
    if (grow(&b->m->joints, &b->cap_joints, b->m->n_joints + 1, sizeof *b->m->joints) != ROZ_OK)
        return ROZ_ENOMEM;
    roz__mjcf_joint_t *j = &b->m->joints[b->m->n_joints++];
    memset(j, 0, sizeof *j);
    j->name = name;
    if (free) {
        j->type = "free";
        return ROZ_OK;
    }
    j->type = joint_type(value(d, k, cls, "type", FIELD(joint_type)));
    j->limited = limited(value(d, k, cls, "actuatorfrclimited", FIELD(joint_limited)),
                         value(d, k, cls, "actuatorfrcrange", FIELD(joint_range)), j->range);
    return ROZ_OK;
}

static int walk(const roz__mjcf_doc_t *d, build_t *b, long body, const char *cls, int depth)
{
    for (long k = d->nodes[body].first; k >= 0; k = d->nodes[k].next) {
        const char *tag = d->nodes[k].tag;
        int rc = ROZ_OK;
        if (strcmp(tag, "body") == 0 || strcmp(tag, "worldbody") == 0) {
            const char *child = attr(d, k, "childclass");
            if (depth < MAX_NESTING * (ROZ_MJCF_MAX_DEPTH + 1))
                rc = walk(d, b, k, child != NULL ? child : cls, depth + 1);
        } else if (strcmp(tag, "freejoint") == 0) {
            rc = add_joint(d, b, k, cls, 1);
        } else if (strcmp(tag, "joint") == 0) {
            rc = add_joint(d, b, k, cls, 0);
        }
        if (rc != ROZ_OK)
            return rc;
    }
    return ROZ_OK;
}

static int read_sections(const roz__mjcf_doc_t *d, build_t *b, long root)
{
    roz__mjcf_model_t *m = b->m;
    for (long s = d->nodes[root].first; s >= 0; s = d->nodes[s].next) {
        const char *section = d->nodes[s].tag;
        int actuators = strcmp(section, "actuator") == 0;
        if (strcmp(section, "worldbody") == 0 && walk(d, b, s, "main", 0) != ROZ_OK)
            return ROZ_ENOMEM;
        if (!actuators && strcmp(section, "sensor") != 0)
            continue;
        for (long k = d->nodes[s].first; k >= 0; k = d->nodes[k].next) {
            if (actuators && is_actuator(d->nodes[k].tag)) {
                if (grow(&m->actuators, &b->cap_actuators, m->n_actuators + 1,
                         sizeof *m->actuators) != ROZ_OK)
                    return ROZ_ENOMEM;
                roz__mjcf_actuator_t *a = &m->actuators[m->n_actuators++];
                const char *joint = attr(d, k, "joint");
                double gear[1];
                a->name = attr(d, k, "name");
                a->joint = joint != NULL ? joint : attr(d, k, "jointinparent");
                if (a->joint == NULL)
                    a->joint = "";
                a->gear = floats(value(d, k, "main", "gear", FIELD(act_gear)), gear, 1) >= 1
                              ? gear[0]
                              : 1.0;
                a->limited = limited(value(d, k, "main", "forcelimited", FIELD(act_limited)),
                                     value(d, k, "main", "forcerange", FIELD(act_range)),
                                     a->range);
            } else if (!actuators) {
                if (grow(&m->sensors, &b->cap_sensors, m->n_sensors + 1, sizeof *m->sensors) !=
                    ROZ_OK)
                    return ROZ_ENOMEM;
                roz__mjcf_sensor_t *x = &m->sensors[m->n_sensors++];
                x->name = attr(d, k, "name");
                x->type = d->nodes[k].tag;
                x->site = attr(d, k, "site");
            }
        }
    }
    return ROZ_OK;
}

int roz__mjcf_read(const char *path, roz__mjcf_model_t *out, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    roz__mjcf_doc_t *d = calloc(1, sizeof *d);
    if (d == NULL) {
        roz_format(err, errlen, "%s: no memory to read it", path);
        return ROZ_ENOMEM;
    }
    out->doc = d;
    /* MuJoCo takes every include's path from the main model's folder */
    const char *slash = strrchr(path, '/');
    size_t dl = slash != NULL ? (size_t)(slash - path) + 1 : 0;
    if (strlen(path) + 1 > sizeof d->dir) {
        roz_format(err, errlen, "%s: the path is longer than %d bytes", path,
                   ROZ_MJCF_PATH_MAX - 1);
        return ROZ_EINVAL;
    }
    memcpy(d->dir, path, dl);
    d->dir[dl] = '\0';
    size_t len;
    char *text = read_file(d, path, path, &len, err, errlen);
    long root = text != NULL ? parse(d, text, len, path, err, errlen) : -1;
    if (root < 0)
        return ROZ_EINVAL;
    if (strcmp(d->nodes[root].tag, "mujoco") != 0) {
        roz_format(err, errlen, "%s: not an MJCF model (its root is <%s>, not <mujoco>)", path,
                   d->nodes[root].tag);
        return ROZ_EINVAL;
    }
    d->model = path;
    if (expand(d, root, NULL, 0, err, errlen) != ROZ_OK)
        return ROZ_EINVAL;
    int nomem = 0;
    for (long k = d->nodes[root].first; k >= 0; k = d->nodes[k].next) {
        if (strcmp(d->nodes[k].tag, "default") == 0)
            add_class(d, k, NULL, &nomem);
    }
    build_t b = { out, 0, 0, 0 };
    if (nomem || read_sections(d, &b, root) != ROZ_OK) {
        roz_format(err, errlen, "%s: no memory to read it", path);
        return ROZ_ENOMEM;
    }
    return ROZ_OK;
}

void roz__mjcf_free(roz__mjcf_model_t *m)
{
    roz__mjcf_doc_t *d = m->doc;
    if (d != NULL) {
        for (size_t i = 0; i < d->n_texts; i++)
            free(d->texts[i]);
        free(d->texts);
        free(d->nodes);
        free(d->attrs);
        free(d->classes);
        free(d);
    }
    free(m->joints);
    free(m->actuators);
    free(m->sensors);
    memset(m, 0, sizeof *m);
}
