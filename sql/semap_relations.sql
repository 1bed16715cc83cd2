-- SEMAP's spatial relations in SQL (needs sql/semap_schema.sql). The same semantics as the C++
-- engine (include/scene_graph_tracker/relations/spatial_relations.hpp); test_semap_sql checks
-- that both give the same answers.
--
-- A reference R has an oriented box (its class's box moved by its pose), extents e = max - min.
-- Projection toward a side: R's cross-section extruded outward from that face by factor x the
-- extent along that axis (front +x, back -x, left +y, right -y, top +z, bottom -z, R's frame).
-- Halfspace: the same, also widened by +-factor x extent along the two other axes.
--   T on R         strict: top projection contains T; relaxed: intersects T; both: distance < on_max
--   T in R         strict: R contains T; relaxed: contains or intersects T
-- Containment may take a tolerance (m): corners up to that far outside still count as inside.
--   directional    strict: the side's projection contains T; relaxed: its halfspace intersects T
--
-- Containment: every region is a box in R's own frame ([lo, hi], semap_bounds). T's box is moved
-- into R's frame with ST_Affine and its 3D extent (Box3D: exact, double precision) compared with
-- [lo, hi]: T is inside exactly when its 8 corners are. Not used, with reasons:
--   SFCGAL's exact ST_3DDifference / ST_3DIntersection + ST_Volume: same answers, but ~0.4 s per
--     pair of rotated boxes in SFCGAL 1.4 (test_semap_sql cross-checks a few pairs);
--   ST_3DIntersects(solid, corner point): PostGIS 3.3 did not return (10 s timeout) for a point on
--     a face (the centre of one), so boxes that share a face could hang the query.
-- Intersection: ST_3DIntersects on the solids (true also when one is inside the other).
-- Distance: ST_3DDistance on the solids (0 when they overlap).

CREATE OR REPLACE FUNCTION semap_relation_names() RETURNS text[] LANGUAGE sql IMMUTABLE AS $$
  SELECT ARRAY['on', 'in', 'left_of', 'right_of', 'in_front_of', 'behind', 'above', 'below']
$$;

-- The side of the reference a directional relation looks at.
CREATE OR REPLACE FUNCTION semap_side(relation text) RETURNS text LANGUAGE sql IMMUTABLE STRICT AS $$
  SELECT CASE relation WHEN 'on' THEN 'top' WHEN 'above' THEN 'top' WHEN 'below' THEN 'bottom'
    WHEN 'left_of' THEN 'left' WHEN 'right_of' THEN 'right' WHEN 'in_front_of' THEN 'front'
    WHEN 'behind' THEN 'back' END
$$;

-- R's box (side 'box'), or its projection (widen = false) / halfspace (widen = true) toward
-- `side`, in R's object frame: ARRAY[min x, min y, min z, max x, max y, max z].
CREATE OR REPLACE FUNCTION semap_bounds(c object_class, side text, factor float8, widen boolean)
RETURNS float8[] LANGUAGE plpgsql IMMUTABLE STRICT AS $$
DECLARE
  lo float8[] := ARRAY[c.min_x, c.min_y, c.min_z];
  hi float8[] := ARRAY[c.max_x, c.max_y, c.max_z];
  e float8[] := ARRAY[c.max_x - c.min_x, c.max_y - c.min_y, c.max_z - c.min_z];
  axis integer := CASE WHEN side IN ('front', 'back') THEN 1 WHEN side IN ('left', 'right') THEN 2 ELSE 3 END;
  k integer;
BEGIN
  IF side = 'box' THEN
    RETURN lo || hi;
  ELSIF side NOT IN ('front', 'back', 'left', 'right', 'top', 'bottom') THEN
    RAISE EXCEPTION 'semap: unknown side %', side;
  END IF;
  IF side IN ('front', 'left', 'top') THEN
    lo[axis] := hi[axis];
    hi[axis] := hi[axis] + factor * e[axis];
  ELSE
    hi[axis] := lo[axis];
    lo[axis] := lo[axis] - factor * e[axis];
  END IF;
  IF widen THEN
    FOR k IN 1..3 LOOP
      IF k <> axis THEN
        lo[k] := lo[k] - factor * e[k];
        hi[k] := hi[k] + factor * e[k];
      END IF;
    END LOOP;
  END IF;
  RETURN lo || hi;
END
$$;

-- The same region as a solid placed at the reference instance's pose.
CREATE OR REPLACE FUNCTION semap_region(r instance, c object_class, side text, factor float8, widen boolean)
RETURNS geometry LANGUAGE plpgsql IMMUTABLE STRICT AS $$
DECLARE
  b float8[] := semap_bounds(c, side, factor, widen);
BEGIN
  RETURN semap_place(semap_aabb(b[1], b[2], b[3], b[4], b[5], b[6]), r.x, r.y, r.z, r.qw, r.qx, r.qy, r.qz);
END
$$;

-- Everything any relation to R can reach: R's box grown by factor x extent on every side.
CREATE OR REPLACE FUNCTION semap_reach(r instance, c object_class, factor float8)
RETURNS geometry LANGUAGE sql IMMUTABLE STRICT AS $$
  SELECT semap_place(semap_aabb(
      c.min_x - factor * (c.max_x - c.min_x), c.min_y - factor * (c.max_y - c.min_y),
      c.min_z - factor * (c.max_z - c.min_z), c.max_x + factor * (c.max_x - c.min_x),
      c.max_y + factor * (c.max_y - c.min_y), c.max_z + factor * (c.max_z - c.min_z)),
    r.x, r.y, r.z, r.qw, r.qx, r.qy, r.qz)
$$;

-- Does R's region `bounds` (semap_bounds, R's frame) contain the solid `target` (world)? The
-- target is moved into R's frame (semap_unplace) and its 3D extent compared with the bounds:
-- exact for a region that is a box in R's frame, as all of them are. Corners may lie `tolerance`
-- (+ 1e-9) outside, as in the C++ engine.
CREATE OR REPLACE FUNCTION semap_contains(bounds float8[], r instance, target geometry, tolerance float8 DEFAULT 0)
RETURNS boolean LANGUAGE plpgsql IMMUTABLE STRICT AS $$
DECLARE
  l box3d := Box3D(semap_unplace(target, r.x, r.y, r.z, r.qw, r.qx, r.qy, r.qz));
  tol float8 := tolerance + 1e-9;
BEGIN
  RETURN ST_XMin(l) >= bounds[1] - tol AND ST_YMin(l) >= bounds[2] - tol AND ST_ZMin(l) >= bounds[3] - tol
     AND ST_XMax(l) <= bounds[4] + tol AND ST_YMax(l) <= bounds[5] + tol AND ST_ZMax(l) <= bounds[6] + tol;
END
$$;

CREATE OR REPLACE FUNCTION semap_intersects(a geometry, b geometry)
RETURNS boolean LANGUAGE sql IMMUTABLE STRICT AS $$
  SELECT a &&& b AND ST_3DIntersects(a, b)
$$;

-- Does `relation` hold between target t and reference r (of class rc)? mode: strict | relaxed.
CREATE OR REPLACE FUNCTION semap_holds(relation text, mode text, t instance, r instance, rc object_class,
                                       factor float8 DEFAULT 3.5, on_max_distance float8 DEFAULT 0.02,
                                       tolerance float8 DEFAULT 0)
RETURNS boolean LANGUAGE plpgsql IMMUTABLE STRICT AS $$
DECLARE
  strict_mode boolean;
BEGIN
  IF mode NOT IN ('strict', 'relaxed') THEN
    RAISE EXCEPTION 'semap: mode must be strict or relaxed, not %', mode;
  END IF;
  strict_mode := mode = 'strict';
  IF relation = 'in' THEN
    RETURN semap_contains(semap_bounds(rc, 'box', factor, false), r, t.box, tolerance)
        OR (NOT strict_mode AND semap_intersects(r.box, t.box));
  ELSIF relation = 'on' THEN
    RETURN CASE WHEN strict_mode
      THEN semap_contains(semap_bounds(rc, 'top', factor, false), r, t.box, tolerance)
      ELSE semap_intersects(semap_region(r, rc, 'top', factor, false), t.box) END
      AND ST_3DDistance(t.box, r.box) < on_max_distance;
  ELSIF semap_side(relation) IS NULL THEN
    RAISE EXCEPTION 'semap: unknown relation %', relation;
  ELSIF strict_mode THEN
    RETURN semap_contains(semap_bounds(rc, semap_side(relation), factor, false), r, t.box, tolerance);
  ELSE
    RETURN semap_intersects(semap_region(r, rc, semap_side(relation), factor, true), t.box);
  END IF;
END
$$;

-- The relations that hold now between present instances; each filter is optional (NULL = any).
-- since: when the relation began to hold without a break (relation_history), NULL if not recorded.
--   SELECT * FROM semap_relations('relay_1', NULL, NULL, 'strict');
CREATE OR REPLACE FUNCTION semap_relations(subject_id text DEFAULT NULL, relation_name text DEFAULT NULL,
                                           object_id text DEFAULT NULL, mode text DEFAULT 'strict',
                                           factor float8 DEFAULT 3.5, on_max_distance float8 DEFAULT 0.02,
                                           tolerance float8 DEFAULT 0)
RETURNS TABLE(subject text, relation text, object text, since timestamptz) LANGUAGE sql STABLE AS $$
  WITH t AS (SELECT i FROM instance i WHERE i.present AND NOT i.fixed AND (subject_id IS NULL OR i.id = subject_id)),
       r AS MATERIALIZED (SELECT i, c, semap_reach(i, c, factor) AS reach FROM instance i
             JOIN object_class c ON c.name = i.class_name
             WHERE i.present AND (object_id IS NULL OR i.id = object_id)),
       rel AS (SELECT n FROM unnest(semap_relation_names()) n WHERE relation_name IS NULL OR n = relation_name)
  SELECT (t.i).id, rel.n, (r.i).id, h.since
  FROM t JOIN r ON (t.i).id <> (r.i).id AND r.reach &&& (t.i).box
  CROSS JOIN rel
  LEFT JOIN relation_history h ON h.subject = (t.i).id AND h.relation = rel.n AND h.object = (r.i).id
                               AND h.mode = semap_relations.mode AND h.until IS NULL
  WHERE semap_holds(rel.n, semap_relations.mode, t.i, r.i, r.c, factor, on_max_distance, tolerance)
  ORDER BY 1, 2, 3
$$;

-- The same between two named instances, with no current-instance filter on `present`.
CREATE OR REPLACE FUNCTION semap_holds(relation text, mode text, subject_id text, object_id text,
                                       factor float8 DEFAULT 3.5, on_max_distance float8 DEFAULT 0.02,
                                       tolerance float8 DEFAULT 0)
RETURNS boolean LANGUAGE sql STABLE STRICT AS $$
  SELECT semap_holds(relation, mode, t, r, c, factor, on_max_distance, tolerance)
  FROM instance t, instance r JOIN object_class c ON c.name = r.class_name
  WHERE t.id = subject_id AND r.id = object_id
$$;

-- Objects on / in a reference, and the directional relations of a to b.
CREATE OR REPLACE FUNCTION semap_objects_on(reference text, mode text DEFAULT 'strict')
RETURNS SETOF text LANGUAGE sql STABLE AS $$
  SELECT subject FROM semap_relations(NULL, 'on', reference, mode)
$$;
CREATE OR REPLACE FUNCTION semap_objects_in(reference text, mode text DEFAULT 'strict')
RETURNS SETOF text LANGUAGE sql STABLE AS $$
  SELECT subject FROM semap_relations(NULL, 'in', reference, mode)
$$;
CREATE OR REPLACE FUNCTION semap_directional_relations(a text, b text, mode text DEFAULT 'strict')
RETURNS SETOF text LANGUAGE sql STABLE AS $$
  SELECT relation FROM semap_relations(a, NULL, b, mode) WHERE relation NOT IN ('on', 'in')
$$;

-- The directional relations of a to b as a viewer at (viewer_x, viewer_y) (world frame) looking
-- at b says them: b's box re-expressed in a frame centred at b, z up, x along the horizontal
-- line of sight (from the viewer to b's origin), y to the viewer's left; its extents those of the
-- smallest such box enclosing b. left_of / right_of are the viewer's left and right, in_front_of
-- is between b and the viewer, behind is beyond b. The C++ engine's holdsFromViewpoint with a
-- camera looking at b gives the same answers (test_semap_sql).
CREATE OR REPLACE FUNCTION semap_viewer_relations(a text, b text, mode text, viewer_x float8, viewer_y float8,
                                                  factor float8 DEFAULT 3.5, on_max_distance float8 DEFAULT 0.02,
                                                  tolerance float8 DEFAULT 0)
RETURNS SETOF text LANGUAGE plpgsql STABLE AS $$
DECLARE
  t instance;
  r instance;
  c object_class;
  yaw float8;
  e box3d;
BEGIN
  SELECT * INTO t FROM instance WHERE id = a AND present;
  IF NOT FOUND THEN RETURN; END IF;
  SELECT * INTO r FROM instance WHERE id = b AND present;
  IF NOT FOUND THEN RETURN; END IF;
  yaw := atan2(r.y - viewer_y, r.x - viewer_x);
  -- b in the viewer-aligned frame: at the world origin, turned by yaw; its extents there.
  r.x := 0; r.y := 0; r.z := 0; r.qw := cos(yaw / 2); r.qx := 0; r.qy := 0; r.qz := sin(yaw / 2);
  e := Box3D(semap_unplace(r.box, 0, 0, 0, r.qw, 0, 0, r.qz));
  c.name := 'viewer';
  c.min_x := ST_XMin(e); c.min_y := ST_YMin(e); c.min_z := ST_ZMin(e);
  c.max_x := ST_XMax(e); c.max_y := ST_YMax(e); c.max_z := ST_ZMax(e);
  c.box := semap_aabb(c.min_x, c.min_y, c.min_z, c.max_x, c.max_y, c.max_z);
  r.box := semap_place(c.box, 0, 0, 0, r.qw, 0, 0, r.qz);
  -- The frame's +x points away from the viewer: "in front of b" is its -x side.
  RETURN QUERY SELECT n FROM unnest(semap_relation_names()) n
    WHERE n NOT IN ('on', 'in') AND semap_holds(
      CASE n WHEN 'in_front_of' THEN 'behind' WHEN 'behind' THEN 'in_front_of' ELSE n END,
      mode, t, r, c, factor, on_max_distance, tolerance)
    ORDER BY 1;
END
$$;

-- Where instance `id` was at `at`: its latest pose at or before `at`.
CREATE OR REPLACE FUNCTION semap_where_was(id text, at timestamptz)
RETURNS SETOF pose_history LANGUAGE sql STABLE AS $$
  SELECT * FROM pose_history p WHERE p.instance_id = semap_where_was.id AND p.stamp <= at
  ORDER BY p.stamp DESC LIMIT 1
$$;

-- Record which relations hold at `at` (both modes): open intervals for new ones, close the ones
-- that stopped. Returns how many intervals were opened or closed.
CREATE OR REPLACE FUNCTION semap_update_relations(at timestamptz, factor float8 DEFAULT 3.5,
                                                  on_max_distance float8 DEFAULT 0.02, tolerance float8 DEFAULT 0)
RETURNS integer LANGUAGE plpgsql AS $$
DECLARE
  changed integer := 0;
  k integer;
  m text;
BEGIN
  FOREACH m IN ARRAY ARRAY['strict', 'relaxed'] LOOP
    WITH cur AS (SELECT c.subject, c.relation, c.object FROM semap_relations(NULL, NULL, NULL, m, factor, on_max_distance, tolerance) c),
         closed AS (UPDATE relation_history h SET until = at
                    WHERE h.mode = m AND h.until IS NULL AND NOT EXISTS (
                      SELECT 1 FROM cur WHERE cur.subject = h.subject AND cur.relation = h.relation AND cur.object = h.object)
                    RETURNING 1),
         opened AS (INSERT INTO relation_history (subject, relation, object, mode, since)
                    SELECT cur.subject, cur.relation, cur.object, m, at FROM cur WHERE NOT EXISTS (
                      SELECT 1 FROM relation_history h WHERE h.mode = m AND h.until IS NULL
                        AND cur.subject = h.subject AND cur.relation = h.relation AND cur.object = h.object)
                    ON CONFLICT DO NOTHING
                    RETURNING 1)
    SELECT (SELECT count(*) FROM closed) + (SELECT count(*) FROM opened) INTO k;
    changed := changed + k;
  END LOOP;
  RETURN changed;
END
$$;
