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
--   directional    strict: the side's projection contains T; relaxed: its halfspace intersects T
--
-- Containment: every region is a convex box, and a convex solid contains a box exactly when it
-- contains the box's 8 corners, each tested with PostGIS' native ST_3DIntersects(point, solid).
-- (SFCGAL's exact ST_3DDifference / ST_3DIntersection + ST_Volume give the same answer but take
-- ~0.4 s per pair of rotated boxes in SFCGAL 1.4; the corner test takes ~0.05 ms.)
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

-- R's projection (widen = false) or halfspace (widen = true) toward `side`, in R's object frame.
CREATE OR REPLACE FUNCTION semap_region_local(c object_class, side text, factor float8, widen boolean)
RETURNS geometry LANGUAGE plpgsql IMMUTABLE STRICT AS $$
DECLARE
  lo float8[] := ARRAY[c.min_x, c.min_y, c.min_z];
  hi float8[] := ARRAY[c.max_x, c.max_y, c.max_z];
  e float8[] := ARRAY[c.max_x - c.min_x, c.max_y - c.min_y, c.max_z - c.min_z];
  axis integer := CASE WHEN side IN ('front', 'back') THEN 1 WHEN side IN ('left', 'right') THEN 2 ELSE 3 END;
  k integer;
BEGIN
  IF side IS NULL OR side NOT IN ('front', 'back', 'left', 'right', 'top', 'bottom') THEN
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
  RETURN semap_aabb(lo[1], lo[2], lo[3], hi[1], hi[2], hi[3]);
END
$$;

-- The same region placed at the reference instance's pose.
CREATE OR REPLACE FUNCTION semap_region(r instance, c object_class, side text, factor float8, widen boolean)
RETURNS geometry LANGUAGE sql IMMUTABLE STRICT AS $$
  SELECT semap_place(semap_region_local(c, side, factor, widen), r.x, r.y, r.z, r.qw, r.qx, r.qy, r.qz)
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

-- Does the convex solid `outer_solid` contain the solid `inner_solid`? (all corners inside)
CREATE OR REPLACE FUNCTION semap_contains(outer_solid geometry, inner_solid geometry)
RETURNS boolean LANGUAGE sql IMMUTABLE STRICT AS $$
  SELECT outer_solid &&& inner_solid AND NOT EXISTS (
    SELECT 1 FROM ST_DumpPoints(inner_solid) p WHERE NOT ST_3DIntersects(outer_solid, p.geom))
$$;

CREATE OR REPLACE FUNCTION semap_intersects(a geometry, b geometry)
RETURNS boolean LANGUAGE sql IMMUTABLE STRICT AS $$
  SELECT a &&& b AND ST_3DIntersects(a, b)
$$;

-- Does `relation` hold between target t and reference r (of class rc)? mode: strict | relaxed.
CREATE OR REPLACE FUNCTION semap_holds(relation text, mode text, t instance, r instance, rc object_class,
                                       factor float8 DEFAULT 3.5, on_max_distance float8 DEFAULT 0.02)
RETURNS boolean LANGUAGE plpgsql IMMUTABLE STRICT AS $$
DECLARE
  strict_mode boolean;
BEGIN
  IF mode NOT IN ('strict', 'relaxed') THEN
    RAISE EXCEPTION 'semap: mode must be strict or relaxed, not %', mode;
  END IF;
  strict_mode := mode = 'strict';
  IF relation = 'in' THEN
    RETURN CASE WHEN strict_mode THEN semap_contains(r.box, t.box) ELSE semap_intersects(r.box, t.box) END;
  ELSIF relation = 'on' THEN
    RETURN ST_3DDistance(t.box, r.box) < on_max_distance AND CASE WHEN strict_mode
      THEN semap_contains(semap_region(r, rc, 'top', factor, false), t.box)
      ELSE semap_intersects(semap_region(r, rc, 'top', factor, false), t.box) END;
  ELSIF semap_side(relation) IS NULL THEN
    RAISE EXCEPTION 'semap: unknown relation %', relation;
  ELSIF strict_mode THEN
    RETURN semap_contains(semap_region(r, rc, semap_side(relation), factor, false), t.box);
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
                                           factor float8 DEFAULT 3.5, on_max_distance float8 DEFAULT 0.02)
RETURNS TABLE(subject text, relation text, object text, since timestamptz) LANGUAGE sql STABLE AS $$
  WITH t AS (SELECT i FROM instance i WHERE i.present AND (subject_id IS NULL OR i.id = subject_id)),
       r AS (SELECT i, c, semap_reach(i, c, factor) AS reach FROM instance i
             JOIN object_class c ON c.name = i.class_name
             WHERE i.present AND (object_id IS NULL OR i.id = object_id)),
       rel AS (SELECT n FROM unnest(semap_relation_names()) n WHERE relation_name IS NULL OR n = relation_name)
  SELECT (t.i).id, rel.n, (r.i).id, h.since
  FROM t JOIN r ON (t.i).id <> (r.i).id AND r.reach &&& (t.i).box
  CROSS JOIN rel
  LEFT JOIN relation_history h ON h.subject = (t.i).id AND h.relation = rel.n AND h.object = (r.i).id
                               AND h.mode = semap_relations.mode AND h.until IS NULL
  WHERE semap_holds(rel.n, semap_relations.mode, t.i, r.i, r.c, factor, on_max_distance)
  ORDER BY 1, 2, 3
$$;

-- The same between two named instances, with no current-instance filter on `present`.
CREATE OR REPLACE FUNCTION semap_holds(relation text, mode text, subject_id text, object_id text,
                                       factor float8 DEFAULT 3.5, on_max_distance float8 DEFAULT 0.02)
RETURNS boolean LANGUAGE sql STABLE STRICT AS $$
  SELECT semap_holds(relation, mode, t, r, c, factor, on_max_distance)
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

-- Where instance `id` was at `at`: its latest pose at or before `at`.
CREATE OR REPLACE FUNCTION semap_where_was(id text, at timestamptz)
RETURNS SETOF pose_history LANGUAGE sql STABLE AS $$
  SELECT * FROM pose_history p WHERE p.instance_id = semap_where_was.id AND p.stamp <= at
  ORDER BY p.stamp DESC LIMIT 1
$$;

-- Record which relations hold at `at` (both modes): open intervals for new ones, close the ones
-- that stopped. Returns how many intervals were opened or closed.
CREATE OR REPLACE FUNCTION semap_update_relations(at timestamptz, factor float8 DEFAULT 3.5,
                                                  on_max_distance float8 DEFAULT 0.02)
RETURNS integer LANGUAGE plpgsql AS $$
DECLARE
  changed integer := 0;
  k integer;
  m text;
BEGIN
  FOREACH m IN ARRAY ARRAY['strict', 'relaxed'] LOOP
    WITH cur AS (SELECT c.subject, c.relation, c.object FROM semap_relations(NULL, NULL, NULL, m, factor, on_max_distance) c),
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
