// The three.js scene: map and scan points coloured by class, trajectory and loop lines, the
// current pose; the camera follows the map until the user moves it.
import * as THREE from "three";
import { OrbitControls } from "three/examples/jsm/controls/OrbitControls.js";
import { CLASS_COLORS, LOOP_COLOR, SCAN_COLOR, TRAJECTORY_COLOR } from "./colors.js";

const classColors = CLASS_COLORS.map((c) => new THREE.Color(c.hex));

export class Scene {
  constructor(container) {
    this.renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(1);
    container.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0x111111);
    this.camera = new THREE.PerspectiveCamera(50, 1, 0.1, 5000);
    this.camera.up.set(0, 0, 1);  // the map frame is z up
    this.camera.position.set(-10, -20, 25);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.userMoved = false;
    this.controls.addEventListener("start", () => { this.userMoved = true; });
    this.map = this.addPoints(3);
    this.scan = this.addPoints(2);
    this.trajectory = this.addLines(TRAJECTORY_COLOR);
    this.loops = this.addLines(LOOP_COLOR);
    this.pose = new THREE.Mesh(new THREE.SphereGeometry(0.3), new THREE.MeshBasicMaterial({ color: SCAN_COLOR }));
    this.scene.add(this.pose);
    window.addEventListener("resize", () => this.resize());
    this.resize();
    // Drawn only when something changed: a continuous 60 Hz loop over the whole map costs a
    // core where WebGL runs in software (no GPU), next to the daemon.
    this.dirty = true;
    this.controls.addEventListener("change", () => { this.dirty = true; });
    // New data is drawn at most 5 times a second; dragging the view stays smooth.
    this.lastDraw = 0;
    this.controls.addEventListener("change", () => { this.lastDraw = 0; });
    this.renderer.setAnimationLoop((now) => {
      this.controls.update();
      if (!this.dirty || now - this.lastDraw < 200) return;
      this.dirty = false;
      this.lastDraw = now;
      this.renderer.render(this.scene, this.camera);
    });
  }

  addPoints(size) {
    const geometry = new THREE.BufferGeometry();
    const material = new THREE.PointsMaterial({ size, sizeAttenuation: false, vertexColors: true });
    const points = new THREE.Points(geometry, material);
    this.scene.add(points);
    return points;
  }

  // Drawn over the points: the path runs on the ground the map points cover.
  addLines(color) {
    const material = new THREE.LineBasicMaterial({ color, depthTest: false });
    const lines = new THREE.LineSegments(new THREE.BufferGeometry(), material);
    lines.renderOrder = 1;
    this.scene.add(lines);
    return lines;
  }

  resize() {
    const w = window.innerWidth, h = window.innerHeight;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.dirty = true;
  }

  // sensor_msgs/PointCloud2 with float32 x y z and uint8 label, little-endian (what the bridge
  // sends on /dammloam/map and /dammloam/labelled_cloud).
  setCloud(points, cloud) {
    const offset = Object.fromEntries(cloud.fields.map((f) => [f.name, f.offset]));
    const n = cloud.width * cloud.height;
    const view = new DataView(cloud.data.buffer, cloud.data.byteOffset, cloud.data.byteLength);
    const positions = new Float32Array(3 * n), colors = new Float32Array(3 * n);
    for (let i = 0; i < n; ++i) {
      const base = i * cloud.point_step;
      positions[3 * i] = view.getFloat32(base + offset.x, true);
      positions[3 * i + 1] = view.getFloat32(base + offset.y, true);
      positions[3 * i + 2] = view.getFloat32(base + offset.z, true);
      const color = classColors[cloud.data[base + offset.label]] || classColors[0];
      colors[3 * i] = color.r; colors[3 * i + 1] = color.g; colors[3 * i + 2] = color.b;
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.BufferAttribute(positions, 3));
    geometry.setAttribute("color", new THREE.BufferAttribute(colors, 3));
    geometry.computeBoundingBox();
    points.geometry.dispose();
    points.geometry = geometry;
    this.dirty = true;
    if (points === this.map && !this.userMoved && n > 0) this.frame(geometry.boundingBox);
  }

  // visualization_msgs/MarkerArray of LINE_LIST markers.
  setLines(lines, markerArray) {
    const vertices = [];
    for (const marker of markerArray.markers) {
      for (const p of marker.points) vertices.push(p.x, p.y, p.z);
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.Float32BufferAttribute(vertices, 3));
    lines.geometry.dispose();
    lines.geometry = geometry;
    this.dirty = true;
  }

  setPose(odometry) {
    const p = odometry.pose.pose.position;
    this.pose.position.set(p.x, p.y, p.z);
    this.dirty = true;
  }

  // Looks at the whole map from above and behind.
  frame(box) {
    const center = box.getCenter(new THREE.Vector3());
    const size = box.getSize(new THREE.Vector3());
    const extent = Math.max(size.x, size.y, 5);
    this.controls.target.copy(center);
    this.camera.position.set(center.x, center.y - 0.3 * extent, center.z + 0.75 * extent);
  }
}
